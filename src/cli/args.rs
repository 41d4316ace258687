//! Command-line arguments of the `mechanism` binary (clap derive).
//!
//! Numeric options accept values that start with `-` (`--t-end -1`), so that the range
//! checks of [`super::validate`] answer with the allowed range instead of clap's hint to
//! write `-- -1`.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};

/// What `--help` says after the options: the exit statuses.
pub const EXIT_CODES: &str = "Exit status: 0 success; 1 invalid input or a failed run (one \
line on stderr; once simulate or inverse has claimed its output folder, its summary.json says \
status failed, where and why); 2 a usage error: an unknown option, a missing argument, a value \
that is not a number (one line on stderr).";

/// Declared closed-loop mechanisms: derived equations, forward and inverse dynamics, plots.
///
/// With no command, runs `simulate spatial_crank_slider`: the seed paper's spatial
/// crank-slider for 10 s under tau = 0.005 sin(2 pi t), writing out/spatial_crank_slider/.
#[derive(Debug, Parser)]
#[command(name = "mechanism", version, about, long_about = None, after_help = EXIT_CODES)]
pub struct Cli {
    /// What to do (default: simulate the seed paper's spatial crank-slider).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the built-in mechanisms with their coordinates n, constraint rows m and degrees of freedom.
    #[command(after_help = EXIT_CODES)]
    List,
    /// Print the derived M, C, g, Phi, Phi_q, gamma and tau of a mechanism.
    #[command(after_help = EXIT_CODES)]
    Equations {
        /// A built-in mechanism name (see `mechanism list`) or a path to a .mech file.
        mechanism: String,
        /// Print LaTeX instead of plain text.
        #[arg(long)]
        latex: bool,
    },
    /// Forward dynamics: assemble from the independent coordinates, then integrate.
    #[command(after_help = EXIT_CODES)]
    Simulate(SimulateArgs),
    /// Inverse dynamics: the driving force needed for a prescribed motion, and the joint reactions.
    #[command(after_help = EXIT_CODES)]
    Inverse(InverseArgs),
    /// Linearise about an equilibrium or a steady motion (cyclic coordinates at constant
    /// rates) in minimal variables: print the eigenvalues, write linearization.json.
    #[command(after_help = EXIT_CODES)]
    Linearize(LinearizeArgs),
    /// Convert a URDF robot description into a .mech declaration.
    ///
    /// One link block per URDF link, parents first; revolute, continuous, prismatic and
    /// fixed joints; gravity 9.81 m/s^2 along -z. `<dynamics>` damping on request
    /// (--damping); geometry, materials, transmissions and friction are not imported.
    #[command(after_help = EXIT_CODES)]
    Import(ImportArgs),
}

/// `mechanism linearize` options.
#[derive(Debug, Clone, clap::Args)]
pub struct LinearizeArgs {
    /// A built-in mechanism name (see `mechanism list`) or a path to a .mech file.
    pub mechanism: String,
    /// Override a parameter's declared default, e.g. `--set v=4` (repeatable); the declared
    /// initial values that depend on it follow.
    #[arg(long = "set", value_name = "PARAM=VALUE")]
    pub set: Vec<String>,
    /// Initial value of an independent coordinate or of its rate (`--init 'der(phi)=3'`):
    /// the state linearised about.
    #[arg(long = "init", value_name = "COORD=VALUE")]
    pub init: Vec<String>,
    /// Output folder for linearization.json (default: `out/<mechanism>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Options shared by `simulate` and `inverse`.
#[derive(Debug, Clone, clap::Args)]
pub struct CommonArgs {
    /// A built-in mechanism name (see `mechanism list`) or a path to a .mech file.
    pub mechanism: String,
    /// End time of the run, in seconds: > 0, at most 1e9.
    #[arg(
        long,
        default_value_t = 10.0,
        value_name = "S",
        allow_hyphen_values = true
    )]
    pub t_end: f64,
    /// Output samples per simulated second: > 0.
    #[arg(
        long,
        default_value_t = 100.0,
        value_name = "K",
        allow_hyphen_values = true
    )]
    pub samples_per_second: f64,
    /// Override a parameter's declared default, e.g. `--set l2=0.35` (repeatable).
    #[arg(long = "set", value_name = "PARAM=VALUE")]
    pub set: Vec<String>,
    /// Initial value of an independent coordinate (`--init phi=0.5`), of its rate
    /// (`--init 'der(phi)=3'`), or a new guess for a dependent one to pick an assembly branch
    /// (in `inverse`: a guess for a coordinate that is not driven, to pick the branch).
    #[arg(long = "init", value_name = "COORD=VALUE")]
    pub init: Vec<String>,
    /// Output folder (default: `out/<mechanism>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Do not write animation.html and the strobe figure mechanism.png/svg (written when the
    /// mechanism declares a `draw` section).
    #[arg(long)]
    pub no_animation: bool,
    /// Plane of the strobe figure: auto (a planar drawing face on, a spatial one oblique),
    /// xy, xz, yz or oblique.
    #[arg(long, value_enum, default_value_t = ViewArg::Auto)]
    pub view: ViewArg,
    /// Instants superimposed in the strobe figure, evenly spaced over the first period (or
    /// revolution) of the first independent coordinate when it has one, else over the run
    /// (1 to 100).
    #[arg(
        long,
        default_value_t = 12,
        value_name = "K",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..=100)
    )]
    pub strobe: u32,
    /// Time-series figures: auto (one per coordinate up to 12 coordinates, else the
    /// overview), all (one per coordinate), overview (every coordinate in one heat map) or
    /// none; the constraint error (simulate) and driving torque (inverse) come with all but
    /// none.
    #[arg(long, value_enum, default_value_t = FiguresArg::Auto)]
    pub figures: FiguresArg,
}

/// Which time-series figures a run writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FiguresArg {
    /// One per coordinate up to 12 coordinates, else the overview.
    Auto,
    /// One figure per coordinate.
    All,
    /// Every coordinate over time in one heat map.
    Overview,
    /// No time-series figures.
    None,
}

impl FiguresArg {
    /// The figure set for a mechanism of `n` coordinates.
    pub fn resolve(self, n: usize) -> mechanism::output::Figures {
        use mechanism::output::Figures;
        match self {
            Self::Auto => Figures::auto(n),
            Self::All => Figures::All,
            Self::Overview => Figures::Overview,
            Self::None => Figures::None,
        }
    }
}

/// View planes of the strobe figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ViewArg {
    /// A planar drawing face on, a spatial one oblique.
    Auto,
    /// x right, y up.
    Xy,
    /// x right, z up.
    Xz,
    /// y right, z up.
    Yz,
    /// Oblique, from azimuth -50 deg and elevation 25 deg, z up.
    Oblique,
}

/// `mechanism simulate` options.
#[derive(Debug, Clone, clap::Args)]
pub struct SimulateArgs {
    /// Mechanism, time span, parameters, initial values, output folder.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Time integrator.
    #[arg(long, value_enum, default_value_t = IntegratorArg::Dop853)]
    pub integrator: IntegratorArg,
    /// Relative error tolerance of the adaptive integrators: at least 1e-15, below 1.
    #[arg(
        long,
        default_value_t = 1e-10,
        value_name = "R",
        allow_hyphen_values = true
    )]
    pub rtol: f64,
    /// Absolute error tolerance of the adaptive integrators: > 0, finite.
    #[arg(
        long,
        default_value_t = 1e-10,
        value_name = "A",
        allow_hyphen_values = true
    )]
    pub atol: f64,
    /// Step size in seconds (rk4 and hht; the initial step of the adaptive ones): > 0, at
    /// most --t-end.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub step: Option<f64>,
    /// How the constraints are kept: projection onto Phi = 0 and Phi_q q' = -Phi_t after each
    /// step (default), Baumgarte feedback, or none.
    #[arg(long, value_enum, default_value_t = StabilizationArg::Projection)]
    pub stabilization: StabilizationArg,
}

/// `mechanism inverse` options.
#[derive(Debug, Clone, clap::Args)]
pub struct InverseArgs {
    /// Mechanism, time span, parameters, initial values, output folder.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Prescribed motion of a coordinate as an expression of t, e.g. `phi = 2*pi*t` (repeatable).
    #[arg(long, required = true, value_name = "'COORD = f(t)'")]
    pub drive: Vec<String>,
}

/// `mechanism import` options.
#[derive(Debug, Clone, clap::Args)]
pub struct ImportArgs {
    /// The URDF file (a regular file of at most 16 MiB; run xacro first on a .xacro).
    #[arg(value_name = "ROBOT.urdf")]
    pub urdf: PathBuf,
    /// Write the declaration to this file instead of printing it.
    #[arg(long, value_name = "FILE.mech")]
    pub out: Option<PathBuf>,
    /// Lock a movable joint at q = 0, writing it as fixed (repeatable). 0 must be within
    /// the joint's limits. A joint with <mimic> left free is held to its master by a
    /// constraint row.
    #[arg(long = "lock", value_name = "JOINT")]
    pub lock: Vec<String>,
    /// The struct name (default: the robot's name in CamelCase).
    #[arg(long, value_name = "STRUCT")]
    pub name: Option<String>,
    /// Import each moving joint's <dynamics damping> b as the force -b q' on its
    /// coordinate (Coulomb friction is not imported).
    #[arg(long)]
    pub damping: bool,
    /// Write every angle (joint rpy, inertia rpy) within RAD of a multiple of pi/2 as
    /// that multiple (0 included; at most 1e-3), e.g. 1e-9 for a file rounded to 11
    /// decimals (1.57079632679); the header states how far the angles moved. Default:
    /// nonzero multiples within 1e-12 only.
    #[arg(long, value_name = "RAD")]
    pub snap_angles: Option<f64>,
    /// Let the root link float: a free-flyer joint `root_joint` (Pinocchio's layout: q =
    /// [position, quaternion x y z w, joints], v = [velocity, angular velocity in the root
    /// frame, joint rates]). Refused for a robot fixed by a `world` link.
    #[arg(long)]
    pub floating: bool,
}

/// Integrators offered on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// Classical fixed-step Runge-Kutta, order 4.
    Rk4,
    /// Dormand-Prince 5(4), adaptive, with dense output.
    Dopri5,
    /// Dormand-Prince 8(5,3) (Hairer's DOP853), adaptive, with dense output.
    Dop853,
    /// Hilber-Hughes-Taylor alpha method, implicit, for stiff mechanisms.
    Hht,
}

/// Constraint stabilisation offered on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StabilizationArg {
    /// Coordinate projection after each accepted step.
    Projection,
    /// Baumgarte feedback (alpha = beta = 10 / s).
    Baumgarte,
    /// No stabilisation: the constraints drift.
    None,
}

/// Refuses a name assigned twice among `items` (`NAME=VALUE` each) of `option` (`--set`,
/// `--init`): which value was meant is not for the tool to guess.
pub fn check_repeated(option: &str, items: &[String]) -> Result<(), super::CliError> {
    for (i, item) in items.iter().enumerate() {
        let Some((name, _)) = split_assignment(item) else {
            continue;
        };
        if let Some(first) = items[..i]
            .iter()
            .find(|other| split_assignment(other).is_some_and(|(n, _)| n == name))
        {
            return Err(super::CliError::Argument(format!(
                "{option} {name} is given twice (`{first}` and `{item}`); give it once"
            )));
        }
    }
    Ok(())
}

/// Splits `NAME=VALUE` (spaces around `=` allowed).
pub fn split_assignment(text: &str) -> Option<(&str, &str)> {
    let (a, b) = text.split_once('=')?;
    let (a, b) = (a.trim(), b.trim());
    (!a.is_empty() && !b.is_empty()).then_some((a, b))
}
