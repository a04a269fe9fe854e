//! The command-line surface (`shared/CLI.md`), parsed by clap.

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Exact level sets of closed triangle meshes (weak-Morse slicing).
#[derive(Parser, Debug)]
#[command(name = "wmslice", version, about)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Slice built-in datasets at their degenerate heights and explain them.
    Demo(DemoArgs),
    /// Write a built-in dataset, or list them.
    Gen(GenArgs),
    /// Validate a mesh: counts, genus, bounding box, exact volume, defects.
    Check(CheckArgs),
    /// Compute exact level sets.
    Slice(SliceArgs),
    /// Re-check a result file exactly against its mesh.
    Verify(VerifyArgs),
    /// The critical heights, the Reeb graph, and layer plans that honour the flats.
    Critical(CriticalArgs),
}

/// Output format of `critical`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CriticalFormat {
    /// The readable report (default).
    Text,
    /// The `wmslice-critical` JSON document.
    Json,
    /// A picture of the Reeb graph.
    Svg,
}

/// `wmslice critical`.
#[derive(Args, Debug)]
pub struct CriticalArgs {
    /// A mesh file (STL, OBJ, OFF, PLY, 3MF; `-` for standard input) or a built-in dataset name.
    pub mesh: String,
    /// Snap coordinates to the grid Q (decimal or p/q) first.
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub snap: Option<String>,
    #[command(flatten)]
    pub repairs: RepairArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = CriticalFormat::Text)]
    pub format: CriticalFormat,
    /// Output file (default, or `-`: stdout).
    #[arg(short, long, value_name = "PATH")]
    pub output: Option<PathBuf>,
    /// Layer height H: audit the uniform plan (which layer prints each
    /// flat, how far off), or with --fit-critical, fit a plan to the flats.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub layer_height: Option<String>,
    /// Fit layers between H/2 and 3H/2 thick with every flat on a boundary.
    #[arg(long, requires = "layer_height")]
    pub fit_critical: bool,
    /// First plane of the audited uniform plan (default: lowest vertex + H/2).
    #[arg(
        long,
        value_name = "Z0",
        allow_hyphen_values = true,
        requires = "layer_height",
        conflicts_with = "fit_critical"
    )]
    pub first: Option<String>,
    /// Worker threads for validation (default: all cores; at most 4 a core or 256, whichever is more).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
}

/// `wmslice demo`.
#[derive(Args, Debug)]
pub struct DemoArgs {
    /// Where to write the HTML viewer of the demo levels.
    #[arg(short, long, value_name = "FILE", default_value = "wmslice-demo.html")]
    pub output: PathBuf,
}

/// `wmslice verify`.
#[derive(Args, Debug)]
pub struct VerifyArgs {
    /// The mesh the result claims to slice (file, `-` for standard input, or built-in dataset name).
    pub mesh: String,
    /// The result: a `wmslice-levelset` JSON written with `--exact` (`-`: standard input).
    pub result: PathBuf,
    /// Snap grid the result was computed with (must match its header).
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub snap: Option<String>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// Which loops go to a Common Layer Interface file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LoopSide {
    /// L-: the material just below each plane (what a layer whose top is the
    /// plane prints). The default.
    Below,
    /// L+: the material just above each plane.
    Above,
    /// S_O: the weak-Morse contour itself.
    Contour,
}

/// `wmslice gen`.
#[derive(Args, Debug)]
pub struct GenArgs {
    /// List the datasets.
    #[arg(long, conflicts_with_all = ["families", "random"])]
    pub list: bool,
    /// List the random families: one line each, with what they exercise.
    #[arg(long, conflicts_with = "random")]
    pub families: bool,
    /// Write a random mesh of `--family` for this seed (deterministic:
    /// the same bytes on every machine and thread count).
    #[arg(
        long,
        value_name = "SEED",
        requires = "family",
        conflicts_with = "name"
    )]
    pub random: Option<u64>,
    /// The random family (see `--families`).
    #[arg(long, value_name = "NAME", requires = "random")]
    pub family: Option<String>,
    /// With `--random`: also write the answers (JSON: every critical
    /// height and the midpoints between them, each with its exact
    /// summary, verified before it is written).
    #[arg(long, value_name = "FILE", requires = "random")]
    pub answers: Option<PathBuf>,
    /// Dataset name.
    #[arg(required_unless_present_any = ["list", "families", "random"])]
    pub name: Option<String>,
    /// Output file (format by extension: stl, obj, off, ply).
    #[arg(short, long, required_unless_present_any = ["list", "families"])]
    pub output: Option<PathBuf>,
}

/// `wmslice check`.
#[derive(Args, Debug)]
pub struct CheckArgs {
    /// A mesh file (`-` for standard input) or a built-in dataset name.
    pub mesh: String,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Snap coordinates to the grid Q first (decimal or p/q).
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub snap: Option<String>,
    #[command(flatten)]
    pub repairs: RepairArgs,
}

/// Output format of `slice`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// The readable summary (default).
    Summary,
    /// The `wmslice-levelset` JSON document (SPEC section 9).
    Json,
    /// One SVG per level (a directory), or one file for a single level.
    Svg,
    /// One self-contained HTML viewer of every level.
    Html,
    /// Common Layer Interface, ASCII.
    Cli,
    /// Common Layer Interface, binary.
    CliBinary,
}

/// `wmslice slice`.
#[derive(Args, Debug)]
pub struct SliceArgs {
    /// A mesh file (STL, OBJ, OFF, PLY, 3MF; `-` for standard input) or a built-in dataset name.
    pub mesh: String,
    /// A level, as typed (0.6, 10.35, 3/5, -1e-3): exact. Repeatable.
    #[arg(long = "at", value_name = "Z", allow_hyphen_values = true)]
    pub at: Vec<String>,
    /// A file with one level per line (same syntax; # comments; `-`:
    /// standard input).
    #[arg(long, value_name = "FILE")]
    pub levels_file: Option<PathBuf>,
    /// Uniform layers of height H (exact: 0.2 is 1/5).
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub layer_height: Option<String>,
    /// First uniform plane (default: lowest vertex + H/2, mid-layer).
    #[arg(
        long,
        value_name = "Z0",
        allow_hyphen_values = true,
        requires = "layer_height"
    )]
    pub first: Option<String>,
    /// Upper bound of the uniform planes (default: highest vertex).
    #[arg(
        long,
        value_name = "Z1",
        allow_hyphen_values = true,
        requires = "layer_height"
    )]
    pub last: Option<String>,
    /// Instead of uniform planes, fit layers between H/2 and 3H/2 thick
    /// with every flat on a layer boundary, and slice each at its middle.
    #[arg(long, requires = "layer_height", conflicts_with_all = ["first", "last", "naive"])]
    pub fit_critical: bool,
    /// Worker threads (default: all cores; at most 4 a core or 256, whichever is more); the output is identical for every N.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Snap coordinates to the grid Q (decimal or p/q) before slicing.
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub snap: Option<String>,
    #[command(flatten)]
    pub repairs: RepairArgs,
    /// Add exact rationals (points, areas) and mesh elements to JSON.
    #[arg(long)]
    pub exact: bool,
    /// The strong-Morse slicer, for comparison only (wrong at degenerate levels).
    #[arg(long)]
    pub naive: bool,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Summary)]
    pub format: Format,
    /// Output file (default, or `-`: stdout).
    #[arg(short, long, value_name = "PATH")]
    pub output: Option<PathBuf>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// After slicing, print to stderr how many loop points took each
    /// number path (grid, per-edge, certified, wide, big) and the wall
    /// time of each step (reading, validation, levels, output): explains a
    /// slow run.
    #[arg(long)]
    pub verbose: bool,
    /// Which loops go to CLI output.
    #[arg(long, value_enum, default_value_t = LoopSide::Below)]
    pub side: LoopSide,
    /// Also write S_NO ridges and valleys as open polylines (CLI output).
    #[arg(long)]
    pub with_ridges: bool,
    /// Draw direction arrows on contours (SVG and HTML).
    #[arg(long)]
    pub arrows: bool,
    /// Write a certificate (hashes, versions, levels, counts, verdict).
    #[arg(long, value_name = "FILE")]
    pub certificate: Option<PathBuf>,
}

/// `--weld` and `--drop-collapsed`, shared by the commands that load a
/// mesh to slice.
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct RepairArgs {
    /// Merge vertices at exactly one point (equal coordinates; an indexed
    /// file's seams) before anything else, as an STL's corners are; exact,
    /// nothing moves; recorded in the JSON header.
    #[arg(long)]
    pub weld: bool,
    /// Remove faces that use one vertex twice (left by welding or snapping;
    /// no area) instead of refusing the mesh; recorded in the JSON header.
    #[arg(long)]
    pub drop_collapsed: bool,
}

impl RepairArgs {
    /// The library's repairs.
    pub fn repairs(self) -> wmslice::mesh::prepare::Repairs {
        wmslice::mesh::prepare::Repairs::from_flags(self.weld, self.drop_collapsed)
    }
}
