//! `nmm plot`: every shipped example drawn as cut (PNG and SVG, with and without the cover
//! mesh), and frames of a run: files written, and the picture changes with the field and
//! the frame; bad requests get one line and a non-zero exit. `nmm figures` writes into
//! `figures/` unless told otherwise.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn nmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

fn ok(args: &[&str]) {
    let out = nmm(args);
    assert!(
        out.status.success(),
        "nmm {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn is_png(p: &Path) -> bool {
    let b = std::fs::read(p).unwrap();
    b.len() > 1000 && b.starts_with(b"\x89PNG\r\n\x1a\n")
}

fn is_svg(p: &Path) -> bool {
    let s = std::fs::read_to_string(p).unwrap();
    s.contains("<svg") && s.contains("</svg>") && s.len() > 1000
}

fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
    v.sort();
    v
}

#[test]
fn every_example_is_drawn_as_cut_in_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let examples = examples();
    assert!(examples.len() >= 5, "{examples:?}");
    for m in examples {
        let stem = m.file_stem().unwrap().to_str().unwrap().to_string();
        let png = dir.path().join(format!("{stem}.png"));
        let svg = dir.path().join(format!("{stem}.svg"));
        let mesh = dir.path().join(format!("{stem}_mesh.png"));
        ok(&["plot", m.to_str().unwrap(), "--out", png.to_str().unwrap()]);
        ok(&["plot", m.to_str().unwrap(), "--out", svg.to_str().unwrap()]);
        ok(&[
            "plot",
            m.to_str().unwrap(),
            "--mesh",
            "--out",
            mesh.to_str().unwrap(),
        ]);
        assert!(is_png(&png) && is_png(&mesh), "{stem}");
        assert!(is_svg(&svg), "{stem}");
        assert_ne!(
            std::fs::read(&png).unwrap(),
            std::fs::read(&mesh).unwrap(),
            "{stem}: --mesh draws more"
        );
        // the picture names the blocks
        let text = std::fs::read_to_string(&svg).unwrap();
        let model = nmm::model::load_model(&m).unwrap();
        for b in model.blocks.iter().take(5) {
            assert!(text.contains(&b.name), "{stem}: block {} not named", b.name);
        }
    }
}

/// A short run of the incline example (40 steps, a frame every 10).
fn incline_run(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/incline.toml"),
    )
    .unwrap()
    .replace("steps = 1000", "steps = 40");
    let text = if text.contains("output_every") {
        text.lines()
            .map(|l| {
                if l.starts_with("output_every") {
                    "output_every = 10"
                } else {
                    l
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    } else {
        text.replace("steps = 40", "steps = 40\noutput_every = 10")
    };
    let model = dir.join("incline.toml");
    std::fs::write(&model, text).unwrap();
    let out = dir.join("run");
    ok(&[
        "run",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    out
}

#[test]
fn run_frames_change_with_field_and_frame() {
    let dir = tempfile::tempdir().unwrap();
    let run = incline_run(dir.path());
    let r = run.to_str().unwrap();
    let f = |name: &str| dir.path().join(name);
    let s = |p: &PathBuf| p.to_str().unwrap().to_string();
    ok(&["plot", r, "--out", &s(&f("last_u.png"))]);
    ok(&[
        "plot",
        r,
        "--last",
        "--field",
        "u",
        "--out",
        &s(&f("last_u2.png")),
    ]);
    ok(&[
        "plot",
        r,
        "--last",
        "--field",
        "sxx",
        "--out",
        &s(&f("last_sxx.png")),
    ]);
    ok(&[
        "plot",
        r,
        "--frame",
        "1",
        "--field",
        "u",
        "--out",
        &s(&f("first_u.png")),
    ]);
    ok(&[
        "plot",
        r,
        "--time",
        "0.011",
        "--field",
        "u",
        "--out",
        &s(&f("time_u.png")),
    ]);
    ok(&[
        "plot",
        r,
        "--last",
        "--field",
        "syy",
        "--out",
        &s(&f("last_syy.svg")),
    ]);
    for n in ["last_u.png", "last_sxx.png", "first_u.png", "time_u.png"] {
        assert!(is_png(&f(n)), "{n}");
    }
    assert!(is_svg(&f("last_syy.svg")));
    let read = |n: &str| std::fs::read(f(n)).unwrap();
    assert_eq!(
        read("last_u.png"),
        read("last_u2.png"),
        "the last frame and field u are the default"
    );
    assert_ne!(
        read("last_u.png"),
        read("last_sxx.png"),
        "the field changes the picture"
    );
    assert_ne!(
        read("last_u.png"),
        read("first_u.png"),
        "the frame changes the picture"
    );
    assert_eq!(
        read("first_u.png"),
        read("time_u.png"),
        "t = 0.011 s is nearest to frame 1 (t = 0.01 s)"
    );
    let svg = std::fs::read_to_string(f("last_syy.svg")).unwrap();
    assert!(
        svg.contains("step 40") && svg.contains("t = 0.04 s"),
        "time in the title"
    );
    assert!(
        svg.contains("σyy (kPa)") || svg.contains("σyy (Pa)"),
        "colour bar with its unit"
    );
    // a sequence: frames 0, 10, 20, 30, 40 → every 2nd frame and the last
    let seq = f("seq");
    ok(&[
        "plot",
        r,
        "--every",
        "2",
        "--field",
        "uy",
        "--out",
        &s(&seq),
    ]);
    let mut names: Vec<String> = std::fs::read_dir(&seq)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "frame_0000.png",
            "frame_0002.png",
            "frame_0004.png",
            "frames.gif"
        ]
    );
    assert!(names[..3].iter().all(|n| is_png(&seq.join(n))));
    // the animation: as many frames as PNGs, one size, and the block moves
    let frames = gif_frames(&seq.join("frames.gif"));
    assert_eq!(frames.len(), 3, "one GIF frame per PNG");
    let (w, h, _) = &frames[0];
    assert_eq!(*w, 1200, "the PNGs' width");
    assert!(frames.iter().all(|f| (f.0, f.1) == (*w, *h)), "one size");
    assert_ne!(frames[0].2, frames[1].2);
    assert_ne!(frames[1].2, frames[2].2);
}

/// The frames of a GIF (width, height, palette indices), decoded by the `gif` crate; the
/// file must start with the GIF89a header.
fn gif_frames(path: &Path) -> Vec<(u16, u16, Vec<u8>)> {
    let bytes = std::fs::read(path).unwrap();
    assert!(
        bytes.starts_with(b"GIF89a"),
        "{}: not a GIF89a",
        path.display()
    );
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(bytes.as_slice()).unwrap();
    let mut out = Vec::new();
    while let Some(f) = decoder.read_next_frame().unwrap() {
        out.push((f.width, f.height, f.buffer.to_vec()));
    }
    out
}

#[test]
fn every_frame_of_a_run_goes_into_the_gif() {
    let dir = tempfile::tempdir().unwrap();
    let run = incline_run(dir.path());
    let seq = dir.path().join("all");
    ok(&[
        "plot",
        run.to_str().unwrap(),
        "--every",
        "1",
        "--out",
        seq.to_str().unwrap(),
    ]);
    let pngs = std::fs::read_dir(&seq)
        .unwrap()
        .filter(|e| {
            let p = e.as_ref().unwrap().path();
            p.extension().is_some_and(|x| x == "png") && is_png(&p)
        })
        .count();
    assert_eq!(pngs, 5, "frames at steps 0, 10, 20, 30, 40");
    let frames = gif_frames(&seq.join("frames.gif"));
    assert_eq!(frames.len(), pngs);
    // in one colour range the sliding block changes colour from frame to frame
    for k in 1..frames.len() {
        assert_ne!(frames[k - 1].2, frames[k].2, "frames {} and {k}", k - 1);
    }
}

#[test]
fn bad_plot_requests_get_one_line_and_a_non_zero_exit() {
    let dir = tempfile::tempdir().unwrap();
    let run = incline_run(dir.path());
    let r = run.to_str().unwrap();
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    for (args, what) in [
        (
            vec!["plot", r, "--field", "vx", "--out", o],
            "unknown field \"vx\"",
        ),
        (
            vec!["plot", r, "--frame", "99", "--out", o],
            "no frame 99 (blocks.pvd has frames 0 … 4)",
        ),
        (
            vec!["plot", r, "--out", "x.gif"],
            "must end in .png or .svg",
        ),
        (
            vec!["plot", "examples/incline.toml", "--frame", "1", "--out", o],
            "give a run's output folder",
        ),
        (
            vec!["plot", "examples/no-such-model.toml", "--out", o],
            "cannot read the model file",
        ),
        (
            vec!["plot", dir.path().to_str().unwrap(), "--out", o],
            "no blocks.pvd",
        ),
    ] {
        let res = nmm(&args);
        assert!(!res.status.success(), "{args:?}");
        let e = String::from_utf8_lossy(&res.stderr);
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(
            e.starts_with("error: ") && e.contains(what),
            "{args:?}: {e}"
        );
    }
}

#[test]
fn figures_go_to_figures_by_default() {
    let out = nmm(&["figures", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("[default: figures]"), "{help}");
}
