//! The `nmm` command line: `run`, `check` (and later `plot`, `verify`).
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "nmm",
    version,
    about = "Numerical Manifold Method for 2-D blocks in contact"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a model and write its outputs into DIR.
    Run {
        model: PathBuf,
        #[arg(long)]
        out: PathBuf,
    },
    /// Validate a model and print a summary without running it.
    Check { model: PathBuf },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { model, out } => run(&model, &out),
        Command::Check { model } => check(&model),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&format!("{e:#}")));
            ExitCode::FAILURE
        }
    }
}

/// Errors are reported on one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn check(path: &std::path::Path) -> anyhow::Result<()> {
    let model = nmm::model::load_model(path)?;
    println!("blocks: {}", model.blocks.len());
    Ok(())
}

fn run(path: &std::path::Path, _out: &std::path::Path) -> anyhow::Result<()> {
    let _model = nmm::model::load_model(path)?;
    anyhow::bail!("running is not yet written")
}
