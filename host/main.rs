//! The `swarf` command line.

use clap::{Parser, Subcommand, ValueEnum};
use swarf::backend::{AnyBackend, Backend, BackendChoice};
use swarf::kernels::{Dim, Dim2, Dim3, Real};
use swarf::{Result, bench, with_backend};

#[derive(Parser)]
#[command(name = "swarf", version = swarf::run::VERSION, about = "GPU meshless simulator for metal cutting")]
struct Cli {
    /// Where to run: the GPU if a CUDA driver and device are present (auto), or force one.
    #[arg(long, value_enum, default_value = "auto", global = true)]
    backend: BackendChoice,
    /// GPU kernels built with the f32 LLVM flags (approximate f32 division and square root, FMA contraction in
    /// every precision): faster, not bitwise equal to the CPU; docs/measurements/notebook.md gives the error they add.
    #[arg(long, global = true)]
    fast_math: bool,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Version, backend, device, driver, embedded PTX targets and precisions.
    Info {
        /// Also the GPU compiler's report of every kernel: registers, spills (local memory), occupancy.
        #[arg(long)]
        kernels: bool,
    },
    /// Run a scene: particle frames (VTU + PVD) and energies (CSV) in the output folder.
    Run(RunArgs),
    /// Validate a scene and print particles, h, c0, dt, steps, memory and the expected run time on this backend.
    Check {
        /// The scene file (TOML); default: the built-in cutting scene, as for `run`.
        scene: Option<std::path::PathBuf>,
        #[arg(long, value_enum)]
        precision: Option<PrecisionChoice>,
        /// Override a scene key (repeatable), as for `run`.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Time standard workloads on the chosen backend.
    Bench(BenchArgs),
    /// List the material library, print a material, evaluate its flow stress, draw flow curves.
    Material {
        /// A material name (omit to list the library).
        name: Option<String>,
        /// Evaluate σ_y at STRAIN,RATE,TEMP (strain [-], rate [1/s], temperature [K]); repeatable.
        #[arg(long = "at", value_name = "STRAIN,RATE,TEMP")]
        at: Vec<String>,
        /// Draw flow curves to this PNG (at the --at rates and temperatures, or three default rates).
        #[arg(long)]
        plot: Option<std::path::PathBuf>,
        /// Read the materials of this folder first (default: the SWARF_MATERIALS folders); then the built-in
        /// library.
        #[arg(long)]
        library: Option<std::path::PathBuf>,
    },
    /// Run a scene over resolutions × precisions (× backends) and report wall time against error (study.csv,
    /// study.md, study.png in the output folder).
    Study(StudyArgs),
    /// Nairn's analytical cutting models (nairn-mpm.md §4): F_c/b of the crack-tip-touching and plastic-bending
    /// models over depths of cut, for the paper's polymer (K 980 MPa, G 376 MPa, σ_y0 25 MPa, G_c 2000 J/m²) or
    /// the properties given.
    Model(ModelArgs),
    /// The fracture strain and diameter of a round tensile specimen's run (the SHTB, docs/damage.md): the
    /// thinnest slab of live particles at the last frame before it falls into two pieces; prints it and writes
    /// neck.json in the run folder.
    Neck {
        /// The run folder (frames written, scene.toml).
        run: std::path::PathBuf,
    },
    /// Draw the PNG plots of a run folder (energies, momenta; forces and temperatures where recorded).
    Plot {
        /// The run folder (holds energy.csv).
        run: std::path::PathBuf,
    },
    /// Draw PNG pictures of a run's particles coloured by a field, with a colour bar and (2D) the tool, a 3D run
    /// seen along -z (<run>/render/).
    Render(RenderArgs),
    /// Run a scene over the cross product of --grid values (one run folder each); a table (sweep.csv, sweep.md)
    /// and plots (sweep-<key>.png) of each run's summary values against every swept key.
    Sweep(SweepArgs),
    /// The chip geometry of a 2D cut's frame along the whole chip: thickness profile, h_min/h_max (valleys/crests),
    /// segment pitch l_seg and frequency, shear-band thickness t_seg, secondary shear layer t_sl, curl radius
    /// r_chip (Klippel Tab. 9.56's quantities; docs/validation.md, "Chip analysis of a frame").
    Chip(ChipArgs),
    /// Identify scene or material parameters against measured cutting forces (an identification file: experiments,
    /// parameters with bounds, objective, optimiser); history.csv, report.md, plots and the best material file.
    Identify(IdentifyArgs),
}

#[derive(clap::Args)]
struct ChipArgs {
    /// A run folder (its last frame) or a frame file (.vtu) of one; the folder's scene.toml gives the tool and dx.
    path: std::path::PathBuf,
    /// The frame's index in the run folder's particles.pvd (default: the last).
    #[arg(long)]
    frame: Option<usize>,
    /// Print the summary.json entry (JSON) instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
struct ModelArgs {
    /// Rake angle [degrees].
    #[arg(long, default_value_t = 30.0)]
    rake: f64,
    /// Coulomb friction coefficient μ on the rake face.
    #[arg(long, default_value_t = 0.0)]
    friction: f64,
    /// Depths of cut [mm], comma separated.
    #[arg(long, default_value = "0.1,0.25,0.5,1,1.5,2,3,5,7")]
    depths: String,
    /// Initial yield stress σ_y0 [Pa] (default: the paper's 25 MPa).
    #[arg(long)]
    yield_stress: Option<f64>,
    /// Plane-strain modulus E' = E/(1 − ν²) [Pa] (default: the paper's, 1122 MPa).
    #[arg(long)]
    plane_modulus: Option<f64>,
    /// Toughness G_c [J/m²] (default: the paper's 2000).
    #[arg(long)]
    toughness: Option<f64>,
    /// Tangent modulus E_T of linear hardening [Pa] (0: elastic–perfectly plastic).
    #[arg(long, default_value_t = 0.0)]
    tangent_modulus: f64,
    /// Rubbing force under the tool F_n^b per unit width [N/m].
    #[arg(long, default_value_t = 0.0)]
    rubbing: f64,
}

#[derive(clap::Args)]
struct RunArgs {
    /// The scene file (TOML), e.g. cases/rings.toml; default: the built-in cutting scene
    /// cases/cutting/v0060.toml (Ti6Al4V, 381 m/min, 0.1 mm, the experiment V0060).
    scene: Option<std::path::PathBuf>,
    /// Continue the run in this folder from its checkpoint.bin (same backend and precision: bit for bit).
    #[arg(long, value_name = "RUN_FOLDER", conflicts_with_all = ["scene", "set", "out", "force"])]
    resume: Option<std::path::PathBuf>,
    /// With --resume: continue even though the run folder's scene.toml, a material or the swarf version differs
    /// from the checkpoint's (the differences are printed; the continuation is not the run it would have been).
    #[arg(long, requires = "resume")]
    accept_changes: bool,
    /// Clear a non-empty run folder before the run (by default a new run refuses one, naming it).
    #[arg(long)]
    force: bool,
    /// Write a checkpoint every this many seconds of simulated time (Ctrl-C and SIGTERM always write one).
    #[arg(long, value_name = "SECONDS")]
    checkpoint_every: Option<f64>,
    /// Also write a checkpoint every this many minutes of wall time, between frames too (0: never).
    #[arg(long, value_name = "MINUTES", default_value_t = 30.0)]
    checkpoint_minutes: f64,
    /// Write the per-particle state (SI, keyed by initial position) after these step counts to
    /// states/state_NNNNNN.csv in the run folder, e.g. 0,1,10,100: for comparisons with other codes
    /// (ci/original/compare.py states).
    #[arg(long, value_name = "STEPS")]
    state_at: Option<String>,
    /// Floating-point precision of the particle state (default: the scene's, else f64).
    #[arg(long, value_enum)]
    precision: Option<PrecisionChoice>,
    /// Override a scene key, e.g. --set time.end=1e-4 --set body.0.velocity=[200.0,0.0] (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder (default runs/<scene name>).
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Print nothing but errors.
    #[arg(long)]
    quiet: bool,
    /// Print the diagnostics of every output step instead of the progress line.
    #[arg(long)]
    verbose: bool,
    /// Also write the frames as HDF5 with an XDMF sidecar (particles.h5, particles.xmf); needs a build with
    /// `--features hdf5`.
    #[arg(long)]
    hdf5: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum PrecisionChoice {
    F32,
    F64,
    /// f32 with compensated positions (each coordinate an f32 pair).
    Mixed,
}

impl PrecisionChoice {
    fn precision(self) -> swarf::scene::Precision {
        match self {
            PrecisionChoice::F32 => swarf::scene::Precision::F32,
            PrecisionChoice::F64 => swarf::scene::Precision::F64,
            PrecisionChoice::Mixed => swarf::scene::Precision::Mixed,
        }
    }
}

#[derive(clap::Args)]
struct StudyArgs {
    /// The scene file (TOML), e.g. cases/cutting/v0060.toml.
    scene: std::path::PathBuf,
    /// Resolution levels: factors on the scene's dx, comma separated; fractions allowed (1,1/2,1/3). The finest
    /// level's f64 run is the reference of the errors.
    #[arg(long, value_delimiter = ',', default_value = "1,1/2")]
    levels: Vec<String>,
    /// Precisions, comma separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "f64,f32")]
    precisions: Vec<PrecisionChoice>,
    /// Backends, comma separated (default: the one --backend selects); the first holds the reference run.
    #[arg(long, value_enum, value_delimiter = ',')]
    backends: Vec<BackendChoice>,
    /// Override a scene key for every run (repeatable), as for `run`; each level then sets discretisation.dx.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder (default runs/study-<scene name>).
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Print nothing but errors.
    #[arg(long)]
    quiet: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Workload {
    /// Cell-list build and state reorder, with the cell-h/cell-2h density comparison.
    Neighbours,
    /// Röthlin's rubber-rings scaling series (2D, N = 4232 … 438 496), the thesis' P100 benchmark.
    Rings,
    /// Return maps per second of the plastic pass, per flow-stress model of the library (10⁶ random states).
    Plasticity,
    /// The whole step of scenes (`--scenes`): ms/step, per-phase times, interactions/s, bandwidth against the
    /// measured copy bandwidth; with `--options`, the step cost of each physics option.
    Step,
    /// Whole runs of one scene (`--scene`, `--set`) per hour and per day as a batched ensemble, at each width of
    /// `--widths`, each measured for `--duration` seconds.
    Ensemble,
    /// The MPM step of an MPM scene (`--scene`, default cases/mpm/nairn-cut.toml; `--set`), `--step-count` steps
    /// from its start, in captured batches and one at a time.
    Mpm,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum PrecisionArg {
    F32,
    F64,
    /// f32 with compensated positions (step and rings workloads).
    Mixed,
    /// f64 then f32.
    Both,
    /// f64, f32 and mixed (step and rings workloads).
    All,
}

#[derive(clap::Args)]
struct BenchArgs {
    #[arg(value_enum, default_value = "neighbours")]
    workload: Workload,
    /// Particle counts, comma separated (1e6 and 1000000 both work).
    #[arg(long, value_delimiter = ',', default_value = "1e6,4e6,16e6")]
    sizes: Vec<String>,
    /// Dimensions, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "2,3")]
    dims: Vec<usize>,
    #[arg(long, value_enum, default_value = "both")]
    precision: PrecisionArg,
    /// Timed repetitions per configuration (the median is reported).
    #[arg(long, default_value_t = 10)]
    repeats: usize,
    /// rings: lattice points per ring side, comma separated (N = 4232 at 80; the thesis series is 80, 160 … 800).
    #[arg(long, value_delimiter = ',', default_value = "80,160,240,320,400,480,560,640,720,800")]
    nbox: Vec<usize>,
    /// rings: steps per size (default: the whole run to the thesis' end time).
    #[arg(long)]
    steps: Option<u64>,
    /// rings: the scene file to scale (default cases/rings.toml); ensemble: the scene run many times (default:
    /// the built-in V0060 cut); mpm: the MPM scene (default cases/mpm/nairn-cut.toml).
    #[arg(long)]
    scene: Option<std::path::PathBuf>,
    /// ensemble, mpm: override a scene key (repeatable; every member's), as for `run --set`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// ensemble: members run at once, comma separated; each width is measured in turn.
    #[arg(long, value_delimiter = ',', default_value = "1,4,8,16")]
    widths: Vec<usize>,
    /// ensemble: seconds of wall time each width keeps starting runs (the running ones then finish).
    #[arg(long, default_value_t = 60.0)]
    duration: f64,
    /// step: the scenes, comma separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "cases/rings.toml,cases/cylinders-3d.toml,cases/impact.toml,cases/cutting/v0060.toml,cases/cutting/reference-cut.toml,cases/cutting/reference-cut-150k.toml"
    )]
    scenes: Vec<std::path::PathBuf>,
    /// step: time the saved states of these run folders (their checkpoint.bin, comma separated) instead of the
    /// scenes' starts.
    #[arg(long, value_delimiter = ',')]
    from: Vec<std::path::PathBuf>,
    /// step, mpm: steps timed per configuration (whole graph batches).
    #[arg(long, default_value_t = 1024)]
    step_count: usize,
    /// step: also time each physics option switched off.
    #[arg(long)]
    options: bool,
}

fn parse_count(s: &str) -> std::result::Result<usize, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v >= 1.0 && *v <= u32::MAX as f64)
        .map(|v| v as usize)
        .ok_or_else(|| format!("--sizes: '{s}' is not a particle count (expected e.g. 1e6 or 1000000)"))
}

/// `--batch`: how many runs an ensemble runs at once, a whole number from 1 to 1024.
fn parse_width(s: &str) -> std::result::Result<usize, String> {
    s.trim()
        .parse::<usize>()
        .ok()
        .filter(|v| (1..=1024).contains(v))
        .ok_or_else(|| format!("'{s}' is not a number of runs at once (expected a whole number from 1 to 1024)"))
}

/// `swarf bench ensemble`: runs per hour of `--scene` (default: the built-in V0060 cut) at each width.
fn bench_ensemble(any: &AnyBackend, a: &BenchArgs) -> Result<()> {
    if let Some(w) = a.widths.iter().find(|w| !(1..=1024).contains(*w)) {
        return Err(swarf::Error::Scene(format!("bench: --widths: {w} is not a width (expected 1 to 1024)")));
    }
    if !(a.duration.is_finite() && a.duration >= 0.0) {
        return Err(swarf::Error::Scene(format!("bench: --duration {}: expected seconds >= 0", a.duration)));
    }
    let scene = load_scene(a.scene.as_deref(), &a.set)?;
    let out = std::env::temp_dir().join(format!("swarf-bench-ensemble-{}", std::process::id()));
    on_interrupt();
    println!("scene {} ({}), overrides {:?}, {} s per width", scene.name, scene.origin, a.set, a.duration);
    println!("{}", bench::ensemble::header());
    for &w in &a.widths {
        let t = bench::ensemble::throughput(any, &scene, w, a.duration, &out);
        let _ = std::fs::remove_dir_all(&out);
        println!("{}", bench::ensemble::row(&t?));
    }
    Ok(())
}

fn run_bench<B: Backend>(b: &B, a: &BenchArgs, sizes: &[usize]) -> Result<()> {
    use swarf::scene::Precision;
    let precs: &[Precision] = match a.precision {
        PrecisionArg::F32 => &[Precision::F32],
        PrecisionArg::F64 => &[Precision::F64],
        PrecisionArg::Mixed => &[Precision::Mixed],
        PrecisionArg::Both => &[Precision::F64, Precision::F32],
        PrecisionArg::All => &[Precision::F64, Precision::F32, Precision::Mixed],
    };
    // The mixed precision differs from f32 in the corrector only: the workloads without one do not take it.
    let integrates = matches!(a.workload, Workload::Step | Workload::Rings);
    if !integrates && precs.contains(&Precision::Mixed) {
        return Err(swarf::Error::Scene(
            "bench: --precision mixed (or all) applies to the step and rings workloads; expected f32, f64 or both"
                .into(),
        ));
    }
    if a.workload == Workload::Plasticity {
        let lib = swarf::material::search::Search::without_scene()
            .library()
            .map_err(|e| swarf::Error::Scene(e.to_string()))?;
        println!("| material (model) | return maps/s |\n|---|---|");
        for (name, rate) in bench::plasticity(b, &lib, 1_000_000, a.repeats)? {
            println!("| {name} | {rate:.3e} |");
        }
        return Ok(());
    }
    if a.workload == Workload::Mpm {
        let path = a.scene.clone().unwrap_or_else(|| "cases/mpm/nairn-cut.toml".into());
        let scene = mpm_scene(Some(&path), &a.set)?.ok_or_else(|| {
            swarf::Error::Scene(format!("bench mpm: {}: not an MPM scene (expected method = \"mpm\")", path.display()))
        })?;
        println!("{}", bench::mpm::header());
        for &p in precs {
            let t = match p {
                Precision::F32 => bench::mpm::time::<B, f32>(b, &scene, a.step_count)?,
                _ => bench::mpm::time::<B, f64>(b, &scene, a.step_count)?,
            };
            println!("{}", bench::mpm::row(&t));
        }
        return Ok(());
    }
    if a.workload == Workload::Step && !a.from.is_empty() {
        return bench::step::checkpoints(b, &a.from, a.step_count);
    }
    if a.workload == Workload::Step {
        return bench::step::scenes(b, &a.scenes, precs, a.step_count, a.options);
    }
    if a.workload == Workload::Rings {
        let scene = a.scene.clone().unwrap_or_else(|| "cases/rings.toml".into());
        println!("{}", bench::rings_header());
        for &p in precs {
            for &k in &a.nbox {
                let t = if p == Precision::F64 {
                    bench::rings::<B, swarf::solver::Solver<B, f64, Dim2>>(b, &scene, k, a.steps, p)?
                } else {
                    bench::rings::<B, swarf::solver::Solver<B, f32, Dim2>>(b, &scene, k, a.steps, p)?
                };
                println!("{}", bench::rings_row(&t));
            }
        }
        return Ok(());
    }
    println!("{}", bench::header());
    for &d in &a.dims {
        for &n in sizes {
            for &p in precs {
                let t = match (d, p) {
                    (2, Precision::F32) => one::<B, f32, Dim2>(b, n, a.repeats)?,
                    (2, _) => one::<B, f64, Dim2>(b, n, a.repeats)?,
                    (_, Precision::F32) => one::<B, f32, Dim3>(b, n, a.repeats)?,
                    _ => one::<B, f64, Dim3>(b, n, a.repeats)?,
                };
                println!("{}", bench::row(&t));
            }
        }
    }
    Ok(())
}

fn one<B: Backend, R: Real, D: Dim>(b: &B, n: usize, repeats: usize) -> Result<bench::NeighbourTimes> {
    bench::neighbours::<B, R, D>(b, n, repeats)
}

/// Ctrl-C (SIGINT), and SIGTERM (what batch schedulers send) and SIGHUP: the run checkpoints before its next
/// batch of steps (within about a second) and stops; a second signal at least a second later stops at once. Signals closer together count once: `timeout -s INT` sends its signal to the command and to its
/// process group, so one timeout delivers two, which must not cost the checkpoint.
fn on_interrupt() {
    static FIRST_MS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let start = std::time::Instant::now();
    let _ = ctrlc::set_handler(move || {
        let now_ms = start.elapsed().as_millis() as u64 + 1;
        if swarf::run::on_signal(&FIRST_MS, now_ms) == swarf::run::SignalAction::Exit {
            std::process::exit(130);
        }
    });
}

fn main() {
    let cli = Cli::parse();
    if cli.fast_math {
        // SAFETY: set before any other thread exists (the backend reads it when it loads the PTX).
        unsafe { std::env::set_var("SWARF_FAST_MATH", "1") };
    }
    let code = match run(cli) {
        Ok(()) => 0,
        Err(e @ swarf::Error::Interrupted { .. }) => {
            eprintln!("\n{e}");
            130
        }
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    };
    std::process::exit(code);
}

fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Info { kernels } => {
            print!("{}", swarf::info::report(cli.backend, kernels)?);
            Ok(())
        }
        Cmd::Run(a) => cmd_run(cli.backend, &a),
        Cmd::Study(a) => cmd_study(cli.backend, &a),
        Cmd::Material { name, at, plot, library } => cmd_material(name, &at, plot, library.as_deref()),
        Cmd::Model(a) => cmd_model(&a),
        Cmd::Render(a) => cmd_render(&a),
        Cmd::Sweep(a) => cmd_sweep(cli.backend, &a),
        Cmd::Identify(a) => cmd_identify(cli.backend, &a),
        Cmd::Chip(a) => cmd_chip(&a),
        Cmd::Check { scene, precision, set } => {
            if let Some(mut sc) = mpm_scene(scene.as_deref(), &set)? {
                if let Some(p) = precision {
                    sc.precision = p.precision();
                }
                let (any, line) = AnyBackend::select(cli.backend)?;
                eprintln!("{line}");
                print!("{}", swarf::mpm::run::check(&any, &sc)?);
                return Ok(());
            }
            let sc = load_scene(scene.as_deref(), &set)?;
            let (any, line) = AnyBackend::select(cli.backend)?;
            eprintln!("{line}");
            let p = precision.map(PrecisionChoice::precision);
            let r = swarf::check::check(&any, &sc, p, 5)?;
            print!("{}", swarf::check::format(&sc, &r));
            Ok(())
        }
        Cmd::Neck { run } => {
            let json = swarf::analysis::neck::to_json(swarf::analysis::neck::run_fracture(&run)?);
            std::fs::write(run.join("neck.json"), format!("{json}\n"))
                .map_err(|e| swarf::Error::Output(format!("{}: {e}", run.display())))?;
            println!("{json}");
            Ok(())
        }
        Cmd::Plot { run } => {
            let drawn = swarf::plot::plot_run(&run).map_err(|e| swarf::Error::Output(e.to_string()))?;
            for d in drawn {
                println!("wrote {}", d.path.display());
                if let Some(w) = d.warning() {
                    eprintln!("warning: {w}");
                }
            }
            Ok(())
        }
        Cmd::Bench(a) => {
            let sizes = a.sizes.iter().map(|s| parse_count(s)).collect::<std::result::Result<Vec<_>, _>>();
            let sizes = match sizes {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("error: {e}");
                    std::process::exit(2);
                }
            };
            if let Some(d) = a.dims.iter().find(|d| !(**d == 2 || **d == 3)) {
                eprintln!("error: --dims: {d} is not a dimension (expected 2 or 3)");
                std::process::exit(2);
            }
            let (any, line) = AnyBackend::select(cli.backend)?;
            eprintln!("{line}");
            if a.workload == Workload::Ensemble {
                return bench_ensemble(&any, &a);
            }
            with_backend!(&any, b => run_bench(b, &a, &sizes))
        }
    }
}

/// `swarf chip`: the chip geometry of a frame, as a table (with Klippel's Tab. 9.56 for V0060) or JSON.
fn cmd_chip(a: &ChipArgs) -> Result<()> {
    if a.frame.is_some() && a.path.is_file() {
        return Err(swarf::Error::Chip(format!("--frame: {} is a frame file already", a.path.display())));
    }
    let r = swarf::cutting::chip_run::analyse_path(&a.path, a.frame)?;
    if a.json {
        let v = swarf::cutting::chip_report::json(r.chip.as_ref(), r.time);
        println!("{}", serde_json::to_string_pretty(&v).map_err(|e| swarf::Error::Output(e.to_string()))?);
        return Ok(());
    }
    println!("{} at t = {:.4e} s (scene {})", r.frame.display(), r.time, r.scene);
    match &r.chip {
        Some(c) => print!("{}", swarf::cutting::chip_report::table(c, r.scene.to_lowercase().starts_with("v0060"))),
        None => println!("no chip: no cross-section of workpiece above the uncut surface at the rake face"),
    }
    Ok(())
}

/// The scene file `path` with `set`, or without one the built-in default scene.
fn load_scene(path: Option<&std::path::Path>, set: &[String]) -> Result<swarf::scene::Scene> {
    match path {
        Some(p) => swarf::scene::Scene::load(p, set).map_err(|e| swarf::Error::Scene(e.to_string())),
        None => swarf::run::default_scene(set),
    }
}

/// The MPM scene at `path`, when the file says `method = "mpm"`.
fn mpm_scene(path: Option<&std::path::Path>, set: &[String]) -> Result<Option<swarf::scene::mpm::MpmScene>> {
    let Some(p) = path else { return Ok(None) };
    let Some(text) = mpm_text(p)? else { return Ok(None) };
    let scene = swarf::scene::mpm::MpmScene::from_str(&text, &p.display().to_string(), set);
    scene.map(Some).map_err(|e| swarf::Error::Scene(e.to_string()))
}

/// The text of the scene file at `p`, when it says `method = "mpm"` (read once).
fn mpm_text(p: &std::path::Path) -> Result<Option<String>> {
    let text = std::fs::read_to_string(p).map_err(|e| swarf::Error::Scene(format!("{}: {e}", p.display())))?;
    let method = swarf::scene::mpm::method_of(&text, &p.display().to_string())
        .map_err(|e| swarf::Error::Scene(e.to_string()))?;
    Ok((method == "mpm").then_some(text))
}

/// `swarf run` of an MPM scene, fresh (`resume` None) or from a run folder's checkpoint (docs/mpm.md).
fn cmd_run_mpm(
    backend: BackendChoice,
    a: &RunArgs,
    scene: swarf::scene::mpm::MpmScene,
    resume: Option<(std::path::PathBuf, Vec<String>)>,
) -> Result<()> {
    let mut scene = scene;
    if let Some(p) = a.precision
        && resume.is_none()
    {
        scene.precision = p.precision();
    }
    let (out, overrides) = match &resume {
        Some((dir, overrides)) => (dir.clone(), overrides.clone()),
        None => (a.out.clone().unwrap_or_else(|| std::path::PathBuf::from("runs").join(&scene.name)), a.set.clone()),
    };
    let (any, line) = AnyBackend::select(backend)?;
    if !a.quiet {
        eprintln!("{line}");
    }
    if resume.is_none() {
        let cleared = swarf::run_folder::prepare(&out, a.force)?;
        if cleared > 0 && !a.quiet {
            eprintln!("--force: cleared {} ({cleared} entries of an earlier run)", out.display());
        }
    }
    on_interrupt();
    let opts = swarf::mpm::run::MpmRunOptions {
        out_dir: out.clone(),
        frames: true,
        quiet: a.quiet,
        overrides,
        resume: resume.is_some(),
    };
    let r = swarf::mpm::run::run(&any, &scene, &opts)?;
    if !a.quiet {
        println!(
            "{}: {} particles ({} specimen), {} nodes, {} steps of {:.3e} s in {:.1} s ({:.4} ms/step) on {}",
            r.name, r.particles, r.specimen, r.nodes, r.steps, r.dt, r.wall_s, r.ms_per_step, r.backend
        );
        if let Some(st) = r.steady {
            println!(
                "steady ({:.3e}..{:.3e} s): F_c = {:.5e} N/m (CoV {:.2} %), F_t = {:.5e} N/m; touching model (Eq. 14, \
                 rubbing {:.4e} N/m): {:.5e} N/m; bending model (Eqs. 18-22): {}",
                st.from,
                st.to,
                st.fc,
                100.0 * st.fc_cov,
                st.ft,
                st.rubbing,
                st.touching_model,
                st.bending_model.map_or("none (Eq. 19 has no root)".to_string(), |b| format!("{b:.5e} N/m"))
            );
        }
        if let Some(e) = r.released {
            println!(
                "released: work {:.5e} J/m - kinetic {:.5e} - strain {:.5e} over {:.4e} m = {:.5e} J/m^2",
                e.work, e.kinetic, e.strain, e.area, e.per_area
            );
        }
        for (what, c) in [("specimen", r.coverage), ("chip", r.chip_coverage)] {
            if let Some(c) = c {
                println!(
                    "glyph test, {what}: area mismatch {:.2} %, gaps {:.2} % ({} holes) of {:.4e} m^2",
                    100.0 * c.mismatch,
                    100.0 * c.gap_share,
                    c.gap_count,
                    c.volume
                );
            }
        }
        println!("output: {}", out.display());
    }
    Ok(())
}

/// `swarf run`: a scene (or a run folder to resume) into its output folder.
fn cmd_run(backend: BackendChoice, a: &RunArgs) -> Result<()> {
    if a.resume.is_none()
        && let Some(scene) = mpm_scene(a.scene.as_deref(), &a.set)?
    {
        return cmd_run_mpm(backend, a, scene, None);
    }
    // An MPM run folder resumes from its checkpoint, its scene.toml read with the checkpoint's overrides.
    if let Some(dir) = &a.resume
        && dir.join("scene.toml").is_file()
        && let Some(text) = mpm_text(&dir.join("scene.toml"))?
    {
        let h = swarf::mpm::checkpoint::header(dir)?;
        let origin = dir.join("scene.toml").display().to_string();
        let mut scene = swarf::scene::mpm::MpmScene::from_str(&text, &origin, &h.overrides)
            .map_err(|e| swarf::Error::Scene(e.to_string()))?;
        scene.precision = swarf::scene::Precision::from_name(&h.precision).unwrap_or(scene.precision);
        return cmd_run_mpm(backend, a, scene, Some((dir.clone(), h.overrides)));
    }
    let (scene, overrides, out) = match &a.resume {
        Some(dir) => {
            let r = swarf::resume::open(dir, a.accept_changes)?;
            for c in &r.accepted {
                eprintln!("warning: resuming with a change (--accept-changes): {c}");
            }
            (r.scene, r.overrides, dir.clone())
        }
        None => {
            let sc = load_scene(a.scene.as_deref(), &a.set)?;
            let out = a.out.clone().unwrap_or_else(|| std::path::PathBuf::from("runs").join(&sc.name));
            (sc, a.set.clone(), out)
        }
    };
    if let Some(c) = a.checkpoint_every
        && !(c.is_finite() && c > 0.0)
    {
        eprintln!("error: --checkpoint-every {c}: expected a positive time in seconds");
        std::process::exit(2);
    }
    if !(a.checkpoint_minutes.is_finite() && a.checkpoint_minutes >= 0.0) {
        eprintln!("error: --checkpoint-minutes {}: expected minutes >= 0 (0: never)", a.checkpoint_minutes);
        std::process::exit(2);
    }
    let state_at = match a.state_at.as_deref().map(swarf::state_table::parse_steps) {
        Some(Ok(steps)) => steps,
        Some(Err(e)) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
        None => Vec::new(),
    };
    let (any, line) = AnyBackend::select(backend)?;
    if !a.quiet {
        eprintln!("{line}");
    }
    // A new run's folder: empty, or cleared with --force once the arguments and backend are known good.
    if a.resume.is_none() {
        let cleared = swarf::run_folder::prepare(&out, a.force)?;
        if cleared > 0 && !a.quiet {
            eprintln!("--force: cleared {} ({cleared} entries of an earlier run)", out.display());
        }
    }
    // Ctrl-C: checkpoint before the next step and stop; a second Ctrl-C stops at once.
    on_interrupt();
    let opts = swarf::run::RunOptions {
        out_dir: out,
        precision: a.precision.map(PrecisionChoice::precision),
        frames: true,
        hdf5: a.hdf5,
        quiet: a.quiet,
        verbose: a.verbose,
        overrides,
        checkpoint_every: a.checkpoint_every,
        resume: a.resume.is_some(),
        checkpoint_wall: (a.checkpoint_minutes > 0.0).then_some(a.checkpoint_minutes * 60.0),
        state_at,
    };
    let r = swarf::run::run(&any, &scene, &opts)?;
    if !a.quiet {
        eprintln!(
            "done: {} particles, {} steps, {:.2} s wall ({:.3e} particle-steps/s), {} {}, output in {}",
            r.particles,
            r.steps,
            r.wall_s,
            r.particles as f64 * r.steps as f64 / r.wall_s.max(1e-9),
            r.backend,
            r.precision,
            opts.out_dir.display()
        );
    }
    Ok(())
}

/// `swarf study`: the scene at several resolutions, precisions and backends.
fn cmd_study(backend: BackendChoice, a: &StudyArgs) -> Result<()> {
    let mut levels = Vec::new();
    for l in &a.levels {
        match swarf::study::Level::parse(l) {
            Ok(level) => levels.push(level),
            Err(e) => {
                eprintln!("error: --levels: {e}");
                std::process::exit(2);
            }
        }
    }
    // Validate the scene (and name its output folder) before a backend is started; an MPM scene by its own reader.
    let name = match mpm_scene(Some(&a.scene), &a.set)? {
        Some(mpm) => mpm.name,
        None => swarf::scene::Scene::load(&a.scene, &a.set).map_err(|e| swarf::Error::Scene(e.to_string()))?.name,
    };
    let out = a.out.clone().unwrap_or_else(|| std::path::PathBuf::from("runs").join(format!("study-{name}")));
    let choices = if a.backends.is_empty() { vec![backend] } else { a.backends.clone() };
    let mut backends = Vec::new();
    for c in choices {
        let (any, line) = AnyBackend::select(c)?;
        if !a.quiet {
            eprintln!("{line}");
        }
        backends.push(any);
    }
    on_interrupt();
    let opts = swarf::study::StudyOptions {
        scene: a.scene.clone(),
        overrides: a.set.clone(),
        levels,
        precisions: a.precisions.iter().map(|p| p.precision()).collect(),
        out_dir: out.clone(),
        quiet: a.quiet,
    };
    swarf::study::study(&backends, &opts)?;
    if !a.quiet {
        eprintln!(
            "study: {} written in {}",
            [swarf::study::CSV, swarf::study::MARKDOWN, swarf::study::PNG].join(", "),
            out.display()
        );
    }
    Ok(())
}

/// `swarf material`: the library, or one material's flow stress at given points and its curves.
fn cmd_material(
    name: Option<String>,
    at: &[String],
    plot: Option<std::path::PathBuf>,
    library: Option<&std::path::Path>,
) -> Result<()> {
    use swarf::material::search::Search;
    let search = library.map_or_else(Search::without_scene, Search::folder);
    let lib = search.library().map_err(|e| swarf::Error::Scene(e.to_string()))?;
    let Some(name) = name else {
        print!("{}", swarf::material::report::list(&lib));
        return Ok(());
    };
    let m = lib.get(&name).map_err(|e| swarf::Error::Scene(e.to_string()))?;
    let mut points = Vec::new();
    for a in at {
        let v: Vec<f64> = a.split(',').filter_map(|x| x.trim().parse::<f64>().ok()).collect();
        if v.len() != 3 || v.iter().any(|x| !x.is_finite()) || v[0] < 0.0 || v[1] < 0.0 || v[2] <= 0.0 {
            eprintln!(
                "error: --at {a}: expected STRAIN,RATE,TEMP, finite numbers with strain >= 0, rate >= 0 1/s, \
                 temperature > 0 K"
            );
            std::process::exit(2);
        }
        points.push([v[0], v[1], v[2]]);
    }
    print!("{}", swarf::material::report::describe(m, &points));
    if let Some(p) = plot {
        swarf::material::report::plot(m, &points, &p).map_err(swarf::Error::Output)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// `swarf model`: Nairn's analytical models over depths of cut (`analytic::nairn::table`).
fn cmd_model(a: &ModelArgs) -> Result<()> {
    use swarf::analytic::nairn::{Specimen, table};
    let bad = |what: &str, got: &dyn std::fmt::Display, expected: &str| {
        swarf::Error::Scene(format!("swarf model: {what} = {got}: expected {expected}"))
    };
    let mut depths = Vec::new();
    for d in a.depths.split(',') {
        match d.trim().parse::<f64>() {
            Ok(h) if h.is_finite() && h > 0.0 => depths.push(h * 1e-3),
            _ => return Err(bad("--depths", &d, "positive depths of cut in mm, comma separated")),
        }
    }
    let paper = Specimen::paper();
    let s = Specimen {
        yield_stress: a.yield_stress.unwrap_or(paper.yield_stress),
        plane_modulus: a.plane_modulus.unwrap_or(paper.plane_modulus),
        toughness: a.toughness.unwrap_or(paper.toughness),
        ..paper
    };
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(s.yield_stress) || !positive(s.plane_modulus) || !positive(s.toughness) {
        return Err(bad("--yield-stress/--plane-modulus/--toughness", &"…", "finite positive values"));
    }
    if !(a.rake.is_finite() && a.rake.abs() < 89.0) {
        return Err(bad("--rake", &a.rake, "an angle in degrees between -89 and 89"));
    }
    if !(a.friction.is_finite() && a.friction >= 0.0) {
        return Err(bad("--friction", &a.friction, "a finite μ >= 0"));
    }
    if !(a.tangent_modulus.is_finite() && a.tangent_modulus >= 0.0 && a.tangent_modulus < s.plane_modulus) {
        return Err(bad("--tangent-modulus", &a.tangent_modulus, "a finite E_T with 0 <= E_T < E'"));
    }
    if !a.rubbing.is_finite() {
        return Err(bad("--rubbing", &a.rubbing, "a finite force per width in N/m"));
    }
    let e = a.tangent_modulus / s.plane_modulus;
    print!("{}", table(&s, a.rake.to_radians(), a.friction, e, a.rubbing, &depths));
    Ok(())
}

#[derive(clap::Args)]
struct RenderArgs {
    /// The run folder (holds particles.pvd and its frames).
    run: std::path::PathBuf,
    /// The field: a frame array (temperature, plastic_strain, von_mises, density, pressure, velocity, ...) or a
    /// short name (T, eps, epsdot, vmises, rho, p, vel).
    #[arg(long, default_value = "vmises")]
    field: String,
    /// The frame: its number in particles.pvd (0 is the first), last, or all.
    #[arg(long, default_value = "last")]
    frame: String,
    /// Output folder (default <run>/render).
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// A 3D run: the axis it is seen along, from its positive side (the page shows (x, y) along z, (z, x) along y,
    /// (y, z) along x).
    #[arg(long, value_enum, default_value = "z")]
    along: Axis,
    /// A 3D run: draw only the particles with MIN <= coordinate <= MAX along --along (in m; default: all of them).
    #[arg(long, value_name = "MIN,MAX", value_parser = parse_slab)]
    slab: Option<(f64, f64)>,
    /// The region shown, in m along the page's axes (default: every particle drawn and the tool), widened on one
    /// axis to equal scales: for a close-up, or a 3D run whose stray particles would shrink the workpiece.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = parse_window)]
    window: Option<swarf::render::draw::Region>,
}

/// An axis of a 3D run's picture.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Axis {
    X,
    Y,
    Z,
}

/// Comma-separated finite numbers for `flag`, `form` naming them (e.g. "MIN,MAX").
fn parse_numbers(s: &str, flag: &str, form: &str) -> std::result::Result<Vec<f64>, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| format!("{flag} {s}: expected {form} in m ({e})"))?;
    if v.iter().all(|x| x.is_finite()) { Ok(v) } else { Err(format!("{flag} {s}: expected finite numbers {form}")) }
}

/// `--slab MIN,MAX`: two finite numbers, MIN <= MAX.
fn parse_slab(s: &str) -> std::result::Result<(f64, f64), String> {
    match parse_numbers(s, "--slab", "MIN,MAX")?[..] {
        [a, b] if a <= b => Ok((a, b)),
        _ => Err(format!("--slab {s}: expected two finite numbers MIN,MAX in m with MIN <= MAX")),
    }
}

/// `--window X0,X1,Y0,Y1`: four finite numbers, X0 < X1 and Y0 < Y1.
fn parse_window(s: &str) -> std::result::Result<swarf::render::draw::Region, String> {
    match parse_numbers(s, "--window", "X0,X1,Y0,Y1")?[..] {
        [x0, x1, y0, y1] if x0 < x1 && y0 < y1 => Ok(((x0, x1), (y0, y1))),
        _ => Err(format!("--window {s}: expected four finite numbers X0,X1,Y0,Y1 in m with X0 < X1 and Y0 < Y1")),
    }
}

#[derive(clap::Args)]
struct SweepArgs {
    /// The scene file (TOML).
    scene: std::path::PathBuf,
    /// A swept scene key and its values, KEY=V1,V2,... as for --set (repeatable: the runs are the cross product).
    #[arg(long = "grid", value_name = "KEY=V1,V2,...", required = true)]
    grid: Vec<String>,
    /// Override a scene key for every run (repeatable), as for `run`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Floating-point precision of every run (default: the scene's, else f64).
    #[arg(long, value_enum)]
    precision: Option<PrecisionChoice>,
    /// Also write each run's particle frames (for `swarf render`).
    #[arg(long)]
    frames: bool,
    /// Output folder (default runs/sweep-<scene name>).
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Runs at once, as one ensemble (default: 8 on a GPU, 1 on the CPU).
    #[arg(long, value_parser = parse_width)]
    batch: Option<usize>,
    /// Print nothing but errors.
    #[arg(long)]
    quiet: bool,
}

/// `swarf render`: pictures of a run folder's frames.
fn cmd_render(a: &RenderArgs) -> Result<()> {
    let frames = swarf::render::Frames::parse(&a.frame).map_err(swarf::Error::Scene)?;
    let opts = swarf::render::RenderOptions {
        run: a.run.clone(),
        field: a.field.clone(),
        frames,
        out: a.out.clone(),
        slab: a.slab,
        along: a.along as usize,
        window: a.window,
    };
    let done = swarf::render::render(&opts)?;
    for w in &done.warnings {
        eprintln!("warning: {w}");
    }
    for f in &done.files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// `swarf sweep`: the scene over a grid of overrides, then its table and plots.
fn cmd_sweep(backend: BackendChoice, a: &SweepArgs) -> Result<()> {
    let grids = a.grid.iter().map(|g| swarf::sweep::Grid::parse(g)).collect::<std::result::Result<Vec<_>, _>>();
    let grids = grids.map_err(swarf::Error::Scene)?;
    // The scene's name names the default folder; every run's scene is validated by `sweep` before any run.
    let name = match mpm_scene(Some(&a.scene), &a.set)? {
        Some(sc) => sc.name,
        None => swarf::scene::Scene::load(&a.scene, &a.set).map_err(|e| swarf::Error::Scene(e.to_string()))?.name,
    };
    let out = a.out.clone().unwrap_or_else(|| std::path::PathBuf::from("runs").join(format!("sweep-{name}")));
    let (any, line) = AnyBackend::select(backend)?;
    if !a.quiet {
        eprintln!("{line}");
    }
    on_interrupt();
    let opts = swarf::sweep::SweepOptions {
        scene: a.scene.clone(),
        overrides: a.set.clone(),
        grids,
        out_dir: out.clone(),
        precision: a.precision.map(PrecisionChoice::precision),
        frames: a.frames,
        quiet: a.quiet,
        width: a.batch,
    };
    let s = swarf::sweep::sweep(&any, &opts)?;
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    if !a.quiet {
        eprintln!(
            "sweep: {} runs; {}, {} and the plots written in {}",
            s.points.len(),
            swarf::sweep::CSV,
            swarf::sweep::MARKDOWN,
            out.display()
        );
    }
    Ok(())
}

#[derive(clap::Args)]
struct IdentifyArgs {
    /// The identification file (TOML), e.g. cases/identify/v0060-de.toml.
    file: std::path::PathBuf,
    /// Output folder (default runs/identify-<file name>).
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Parameter sets per batch (overrides the file's optimizer.batch).
    #[arg(long)]
    batch: Option<usize>,
    /// Identify only these of the file's [[parameter]] keys (comma-separated, e.g. tool.friction); the others keep
    /// the scenes' values. A resumed folder keeps the keys it was started with.
    #[arg(long, value_delimiter = ',')]
    only: Option<Vec<String>>,
    /// Runs at once, as one ensemble (default: 8 on a GPU, 1 on the CPU); changes no result.
    #[arg(long, value_parser = parse_width)]
    width: Option<usize>,
    /// Continue the identification in the output folder from its history.csv.
    #[arg(long)]
    resume: bool,
    /// Run only the [[holdout]] tests: the folder's best set (with --resume) and the compare materials.
    #[arg(long)]
    holdout_only: bool,
    /// Print nothing but errors.
    #[arg(long)]
    quiet: bool,
}

/// `swarf identify`: an identification file's optimisation, batch by batch.
fn cmd_identify(backend: BackendChoice, a: &IdentifyArgs) -> Result<()> {
    let stem = a.file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "identify".into());
    let out = a.out.clone().unwrap_or_else(|| std::path::PathBuf::from("runs").join(format!("identify-{stem}")));
    let (any, line) = AnyBackend::select(backend)?;
    if !a.quiet {
        eprintln!("{line}");
    }
    on_interrupt();
    let opts = swarf::identify::IdentifyOptions {
        file: a.file.clone(),
        out_dir: out.clone(),
        batch: a.batch,
        only: a.only.clone(),
        width: a.width,
        resume: a.resume,
        holdout_only: a.holdout_only,
        quiet: a.quiet,
    };
    let done = match swarf::identify::identify(&any, &opts) {
        // `identify` has said how to resume it; the run's own "swarf run --resume" would mislead.
        Err(swarf::Error::Interrupted { .. }) => std::process::exit(130),
        r => r?,
    };
    for w in &done.warnings {
        eprintln!("warning: {w}");
    }
    if !(a.quiet || a.holdout_only && done.rows.is_empty()) {
        eprintln!(
            "identify: {} evaluations; history.csv, report.md and the plots written in {}",
            done.rows.len(),
            out.display()
        );
        if let Some(m) = &done.material {
            eprintln!("identify: best material {}", m.display());
        }
    }
    Ok(())
}
