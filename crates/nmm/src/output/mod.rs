//! Everything a run writes to its output folder, in generic form: the writers know nothing of
//! NMM types; the simulation fills them with plain numbers, names and cells.
//!
//! # Output folder layout (`nmm run MODEL.toml --out DIR`; every file in `docs/outputs.md`)
//! ```text
//! DIR/
//!   history.csv                one row per step: step,time,<monitor columns...>,iterations
//!   blocks.csv                 the block table: id,name,material,fixed (id = VTK `block`)
//!   summary.json               how the run went: status, steps, iterations, timings, warnings
//!   blocks.pvd                 ParaView collection of the block frames (open this one)
//!   contacts.pvd               ParaView collection of the contact frames
//!   vtk/blocks_000000.vtu      deformed blocks at frame 0: polygons, displacement, stress, ...
//!   vtk/blocks_000010.vtu      ... one frame every `output_every` steps (NNNNNN = step number)
//!   vtk/contacts_000000.vtu    contact points at frame 0 with forces and states
//!   ...
//! ```
//! * [`history`]: `history.csv`, shortest round-trip numbers, flushed as it goes.
//! * [`vtk`]: `.vtu` unstructured grids (base64 binary) and `.pvd` collections, rewritten
//!   after each frame so an interrupted run leaves valid files.
//! * [`plot`]: stacked line plots sharing one x axis, PNG and SVG, with an embedded font.
//!
//! Frame file names are produced by [`frame_file_name`] so that every part of the program
//! agrees on them.

pub mod history;
pub mod plot;
pub mod vtk;

pub use history::HistoryWriter;
pub use plot::{plot_panels, LineStyle, Panel, PlotError, Series, Stroke};
pub use vtk::{write_vtu, Cell, CellKind, DataArray, FieldStrings, Grid, PvdWriter, Values};

/// File name of frame `step` of a series, e.g. `frame_file_name("blocks", 42)` is
/// `blocks_000042.vtu` (at least six digits; more if `step` needs them).
pub fn frame_file_name(series: &str, step: usize) -> String {
    format!("{series}_{step:06}.vtu")
}

#[cfg(test)]
mod tests {
    #[test]
    fn frame_names_are_zero_padded() {
        assert_eq!(super::frame_file_name("blocks", 42), "blocks_000042.vtu");
        assert_eq!(
            super::frame_file_name("contacts", 1_234_567),
            "contacts_1234567.vtu"
        );
    }
}
