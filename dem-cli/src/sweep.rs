//! `dem sweep`: parameter studies and seed repeats as tables of cases, run here (`run`, N at
//! a time) or as a Slurm job array (`slurm.sbatch`, one task per case), then collected into one
//! table with aggregates over seeds (docs/sweep.md).
//!
//! The work is the run layer's, [`dem_run`]: the planner ([`dem_run::plan`]), the runner
//! ([`dem_run::runner`]) and the collector ([`dem_run::collect`]). Here: the flags, the `dem
//! test` command lines the planner checks cases against ([`DemTest`]), the progress bar and
//! the printed lines.

use clap::{Args, Subcommand};
use dem_run::plan::{FlagInfo, TestCommands};
use dem_run::Error;
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

/// `dem sweep` commands.
#[derive(Subcommand)]
pub enum SweepCmd {
    /// Expand a study file into DIR: study.json, cases.jsonl (one case per line, keyed by a
    /// hash of its inputs) and slurm.sbatch (a job array, one task per case).
    Plan(PlanArgs),
    /// Run the cases not yet finished, N at a time (or case I alone: --index I); several
    /// processes (Slurm tasks) may share DIR.
    Run(RunArgs),
    /// Counts, the state of each case, and the time taken (CPU and wall, overall and per axis
    /// value).
    Status(StatusArgs),
    /// One row per case (axis values, collected outputs, status, times) and aggregates over
    /// seeds (n, mean, sd, SE, median) as CSV or JSON.
    Collect(CollectArgs),
}

/// `dem sweep plan` flags.
#[derive(Args)]
pub struct PlanArgs {
    /// The study file (JSON, docs/sweep.md).
    pub study: PathBuf,
    /// The sweep folder: study.json, cases.jsonl, slurm.sbatch; cases/ and logs/ below it.
    #[arg(long)]
    pub out: PathBuf,
    /// Slurm: at most this many array tasks at once (`--array=0-N%T`).
    #[arg(long)]
    pub throttle: Option<usize>,
    /// Slurm: CPUs per task, also each case's worker threads.
    #[arg(long, default_value_t = 1, value_parser = crate::parse_threads)]
    pub cpus_per_task: usize,
    /// Slurm: time limit per task (`MM`, `HH:MM:SS`, `D-HH:MM:SS`).
    #[arg(long, default_value = "01:00:00")]
    pub time: String,
    /// Slurm: partition (default: the cluster's).
    #[arg(long)]
    pub partition: Option<String>,
    /// Slurm: memory per task (`2G`; default: the cluster's).
    #[arg(long)]
    pub mem: Option<String>,
}

/// `dem sweep run` flags.
#[derive(Args)]
pub struct RunArgs {
    /// The sweep folder (`dem sweep plan --out DIR`).
    pub dir: PathBuf,
    /// Cases at once.
    #[arg(long, default_value_t = 1, value_parser = crate::parse_threads)]
    pub jobs: usize,
    /// Worker threads of each case (small specimens scale best one thread each).
    #[arg(long, default_value_t = 1, value_parser = crate::parse_threads)]
    pub threads: usize,
    /// Run case I alone (a Slurm array task: --index $SLURM_ARRAY_TASK_ID); a failed case I
    /// is run again.
    #[arg(long)]
    pub index: Option<usize>,
    /// Run the failed cases again too (without it they are listed and skipped).
    #[arg(long)]
    pub retry_failed: bool,
}

/// `dem sweep status` flags.
#[derive(Args)]
pub struct StatusArgs {
    /// The sweep folder.
    pub dir: PathBuf,
}

/// `dem sweep collect` flags.
#[derive(Args)]
pub struct CollectArgs {
    /// The sweep folder.
    pub dir: PathBuf,
    /// table.csv (and table.aggregates.csv beside it) or table.json.
    #[arg(long)]
    pub out: PathBuf,
    /// Leave out the wall and CPU time columns (for comparing tables of two runs).
    #[arg(long)]
    pub no_timing: bool,
}

pub fn run(cmd: SweepCmd) -> Result<ExitCode, String> {
    let e = |e: Error| e.to_string();
    match cmd {
        SweepCmd::Plan(a) => plan(a).map_err(e),
        SweepCmd::Run(a) => run_cases(a).map_err(e),
        SweepCmd::Status(a) => {
            dem_run::collect::status(&a.dir)
                .map_err(e)?
                .iter()
                .for_each(|l| println!("{l}"));
            Ok(ExitCode::SUCCESS)
        }
        SweepCmd::Collect(a) => {
            let w = dem_run::collect::write(&a.dir, &a.out, !a.no_timing).map_err(e)?;
            println!(
                "{} cases ({} done), {} groups over {} -> {}",
                w.cases,
                w.done,
                w.groups,
                w.seed_axis.as_deref().unwrap_or("(no seed axis)"),
                w.files
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// `dem test <kind>`'s command lines, from this executable's own parser (built once: the
/// planner checks every case against it).
pub struct DemTest(clap::Command);

impl DemTest {
    pub fn new() -> Self {
        DemTest(crate::negative_values(
            crate::test::TestKind::augment_subcommands(clap::Command::new("test")),
        ))
    }

    fn command(&self, kind: &str) -> dem_run::Result<&clap::Command> {
        self.0
            .find_subcommand(kind)
            .ok_or_else(|| Error::input(format!("`dem test {kind}` does not exist")))
    }
}

impl TestCommands for DemTest {
    fn flags(&self, kind: &str) -> dem_run::Result<BTreeMap<String, FlagInfo>> {
        let sub = self.command(kind)?;
        let mut flags = BTreeMap::new();
        for a in sub.get_arguments() {
            if let Some(long) = a.get_long() {
                flags.insert(
                    long.to_string(),
                    FlagInfo {
                        takes_value: a.get_action().takes_values(),
                        is_file: a.get_value_parser().type_id()
                            == std::any::TypeId::of::<PathBuf>(),
                    },
                );
            }
        }
        Ok(flags)
    }

    fn check(&self, kind: &str, args: &[String]) -> dem_run::Result<()> {
        let argv = std::iter::once(kind.to_string()).chain(args.iter().cloned());
        self.command(kind)?
            .clone()
            .try_get_matches_from(argv)
            .map(|_| ())
            .map_err(|e| Error::input(e.to_string()))
    }
}

fn this_exe() -> dem_run::Result<PathBuf> {
    std::env::current_exe().map_err(|e| Error::process(format!("the dem executable's path: {e}")))
}

fn plan(a: PlanArgs) -> dem_run::Result<ExitCode> {
    let slurm = dem_run::plan::Slurm {
        throttle: a.throttle,
        cpus_per_task: a.cpus_per_task,
        time: a.time,
        partition: a.partition,
        mem: a.mem,
    };
    let p = dem_run::plan::write(&a.study, &a.out, &slurm, &DemTest::new(), &this_exe()?)?;
    println!(
        "planned {} cases of `dem test {}` ({}) into {}",
        p.cases.len(),
        p.study.study.base.test,
        p.axes_line(),
        p.dir.display()
    );
    println!(
        "run here: dem sweep run {0} --jobs N; on Slurm: sbatch {0}/{1}",
        p.dir.display(),
        dem_run::case::SBATCH_FILE
    );
    Ok(ExitCode::SUCCESS)
}

/// The runner's lines on stderr, above a bar on a terminal (off one, the lines alone: each
/// case's end is a line already).
struct Shown(Option<ProgressBar>);

impl Shown {
    fn new() -> Self {
        Shown(std::io::stderr().is_terminal().then(|| {
            let b = ProgressBar::new(0);
            if let Ok(s) =
                ProgressStyle::with_template("{elapsed:>5} sweep {bar:30} {pos}/{len} done, {msg}")
            {
                b.set_style(s);
            }
            b
        }))
    }
}

impl dem_run::runner::Report for Shown {
    fn line(&mut self, line: String) {
        match &self.0 {
            Some(b) => b.println(line),
            None => eprintln!("{line}"),
        }
    }

    fn progress(&mut self, done: usize, total: usize, message: &str) {
        if let Some(b) = &self.0 {
            b.set_length(total as u64);
            b.set_position(done as u64);
            b.set_message(message.to_string());
        }
    }
}

fn run_cases(a: RunArgs) -> dem_run::Result<ExitCode> {
    let opts = dem_run::runner::RunOptions {
        dir: a.dir,
        jobs: a.jobs,
        threads: a.threads,
        index: a.index,
        retry_failed: a.retry_failed,
        executor: dem_run::runner::Executor::Process(this_exe()?),
    };
    let mut shown = Shown::new();
    let s = dem_run::runner::run(&opts, &DemTest::new(), &mut shown)?;
    if let Some(b) = shown.0 {
        b.finish_and_clear();
    }
    println!(
        "sweep {}: {} cases: {} done, {} failed, {} running elsewhere, {} pending; this run {}",
        opts.dir.display(),
        s.chosen,
        s.done,
        s.failed,
        s.running,
        s.pending,
        dem_run::runner::fmt_secs(s.wall_s)
    );
    for l in &s.elsewhere {
        println!("{l}");
    }
    if !s.failures.is_empty() {
        println!("failed cases (rerun with --retry-failed after a fix):");
        for f in &s.failures {
            println!("{f}");
        }
        return Ok(ExitCode::from(1));
    }
    if opts.index.is_some() && s.done < s.chosen {
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    //! The planner's checks against `dem test`'s real command lines.
    use super::DemTest;
    use dem_run::case::Case;
    use dem_run::study;
    use std::path::Path;

    fn plan(text: &str) -> Result<Vec<Case>, String> {
        let f = Path::new("s.json");
        let parsed = study::parse(text.as_bytes(), f).map_err(|e| e.to_string())?;
        dem_run::plan::cases(f, &parsed, &DemTest::new()).map_err(|e| e.to_string())
    }

    #[test]
    fn zip_switches_and_keys() {
        let z =
            plan(r#"{"name":"z","base":{"test":"cutting","flags":{"specimen-x":1}}}"#).unwrap_err();
        assert!(
            z.contains("base.flags.specimen-x") && z.contains("not a flag"),
            "{z}"
        );
        let c = plan(
            r#"{"name":"z","base":{"test":"cutting","flags":{"r_min":"0.1mm","r-max":"0.2mm"}},
                "combine":"zip","axes":[{"flag":"depth","values":["1mm","2mm"]},
                {"flag":"delete-fragments","values":[true,false]}]}"#,
        )
        .unwrap();
        assert_eq!(c.len(), 2);
        let a: Vec<String> = ["test", "cutting", "--r-max", "0.2mm", "--r-min", "0.1mm"]
            .map(String::from)
            .to_vec();
        let mut a0 = a.clone();
        a0.extend(["--depth", "1mm", "--delete-fragments"].map(String::from));
        let mut a1 = a.clone();
        a1.extend(["--depth", "2mm"].map(String::from));
        assert_eq!((c[0].argv.clone(), c[1].argv.clone()), (a0, a1));
        assert_eq!(c[1].axes[1], ("delete-fragments".into(), "false".into()));
        // The key is the inputs': the same flags given in another order or spelling agree.
        let d = plan(
            r#"{"name":"other","base":{"test":"cutting","flags":{"r-max":"0.2mm"}},
                "axes":[{"flag":"r-min","values":["0.1mm"]},{"flag":"depth","values":["2mm"]}]}"#,
        )
        .unwrap();
        assert_eq!(d[0].key, c[1].key);
        assert_ne!(c[0].key, c[1].key);
        let e = plan(
            r#"{"name":"z","base":{"test":"cutting"},"axes":[{"flag":"delete-fragments","values":["yes"]}]}"#,
        )
        .unwrap_err();
        assert!(
            e.contains("axes[0].values[0]") && e.contains("switch"),
            "{e}"
        );
    }

    #[test]
    fn sets_axes_give_several_flags_per_value() {
        let c = plan(
            r#"{"name":"s","base":{"test":"cutting","flags":{"r-min":"0.1mm","r-max":"0.2mm"}},
                "axes":[{"name":"damping","sets":[
                    {"name":"local","flags":{"local-damping":0.7}},
                    {"name":"viscous","flags":{"local_damping":0,"contact-damping":0.2}},
                    {"name":"none"}]},
                  {"flag":"depth","values":["1mm","2mm"]}]}"#,
        )
        .unwrap();
        assert_eq!(c.len(), 6);
        assert_eq!(
            c[2].axes,
            vec![
                ("damping".to_string(), "viscous".to_string()),
                ("depth".to_string(), "1mm".to_string())
            ]
        );
        let tail: Vec<&str> = c[2].argv[6..].iter().map(String::as_str).collect();
        assert_eq!(
            tail,
            [
                "--contact-damping",
                "0.2",
                "--local-damping",
                "0",
                "--depth",
                "1mm"
            ]
        );
        assert_eq!(c[4].argv[6..], ["--depth", "1mm"].map(String::from));
        // The key is the flags': a set giving the base's flags is the same case.
        let d = plan(
            r#"{"name":"t","base":{"test":"cutting","flags":{"r-min":"0.1mm","r-max":"0.2mm",
                "depth":"1mm"}},"axes":[{"name":"x","sets":[{"name":"a","flags":{
                "contact-damping":0.2,"local-damping":0}}]}]}"#,
        )
        .unwrap();
        assert_eq!(d[0].key, c[2].key);
        let bad = |axes: &str, want: &[&str]| {
            let e = plan(&format!(
                r#"{{"name":"s","base":{{"test":"cutting","flags":{{"depth":"1mm"}}}},"axes":{axes}}}"#
            ))
            .unwrap_err();
            for w in want {
                assert!(e.contains(w), "{axes}: {e}");
            }
        };
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"depth":"2mm"}}]}]"#,
            &["axes[0].sets[0].flags.depth", "base.flags"],
        );
        bad(
            r#"[{"flag":"speed","values":[1]},{"name":"d","sets":[{"name":"a","flags":{"speed":2}}]}]"#,
            &["axes[1].sets[0].flags.speed", "axes[0]"],
        );
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"tool-friction":0.1}}]},
                {"name":"e","sets":[{"name":"b","flags":{"tool-friction":0.2}}]}]"#,
            &["axes[0].sets[0].flags.tool-friction", "axes[1]"],
        );
        bad(
            r#"[{"flag":"d","sets":[{"name":"a"}]}]"#,
            &["axes[0].flag", "name"],
        );
        bad(r#"[{"sets":[{"name":"a"}]}]"#, &["axes[0].name", "missing"]);
        bad(r#"[{"name":"d","sets":[]}]"#, &["axes[0].sets", "empty"]);
        bad(
            r#"[{"name":"d","sets":[{"name":"a"},{"name":"a"}]}]"#,
            &["axes[0].sets[1].name", "twice"],
        );
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"speeed":2}}]}]"#,
            &["axes[0].sets[0].flags.speeed", "not a flag"],
        );
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"speed":[2]}}]}]"#,
            &["axes[0].sets[0].flags.speed", "not a string"],
        );
        bad(
            r#"[{"name":"d","values":[1]}]"#,
            &["axes[0].name", "only a sets axis"],
        );
    }

    /// Issue 48 D5: a value listed twice in an axis (seeds, values, or sets giving the same
    /// flags) is refused, naming both places, instead of planning two cases of one key.
    #[test]
    fn a_value_listed_twice_is_refused() {
        let base = r#"{"name":"d","base":{"test":"cutting","flags":{"r-min":"0.1mm"}},"axes":"#;
        let e = plan(&format!(r#"{base}[{{"seeds":[1,1,2]}}]}}"#)).unwrap_err();
        assert!(
            e.contains("axes[0].values[1]") && e.contains("axes[0].values[0]"),
            "{e}"
        );
        assert!(e.contains("count twice"), "{e}");
        let e = plan(&format!(
            r#"{base}[{{"flag":"depth","values":["1mm","2mm","1mm"]}}]}}"#
        ))
        .unwrap_err();
        assert!(
            e.contains("axes[0].values[2]") && e.contains("axes[0].values[0]"),
            "{e}"
        );
        let e = plan(&format!(
            r#"{base}[{{"flag":"depth","values":["1mm"]}},{{"name":"damping","sets":[
                {{"name":"a","flags":{{"local-damping":0.7}}}},
                {{"name":"b","flags":{{"local-damping":0.7}}}}]}}]}}"#
        ))
        .unwrap_err();
        assert!(
            e.contains("axes[1].sets[1]") && e.contains("axes[1].sets[0]"),
            "{e}"
        );
        // One depth spelt four ways is one value; a speed in two units likewise.
        for (flag, spellings) in [
            ("depth", ["1mm", "1.0mm", "0.001m", "1000um"]),
            ("speed", ["2m/s", "2000mm/s", "2.0m/s", "2e3mm/s"]),
            // A bare speed is m/s (one parser for every speed flag).
            ("speed", ["2", "2m/s", "2000mm/s", "2.0"]),
        ] {
            for k in 1..spellings.len() {
                let e = plan(&format!(
                    r#"{base}[{{"flag":"{flag}","values":["{}","{}"]}}]}}"#,
                    spellings[0], spellings[k]
                ))
                .unwrap_err();
                assert!(
                    e.contains("axes[0].values[1]") && e.contains("count twice"),
                    "{e}"
                );
            }
        }
        // Distinct values plan as before.
        let ok = plan(&format!(r#"{base}[{{"seeds":[1,2,3]}}]}}"#)).unwrap();
        assert_eq!(ok.len(), 3);
        let ok = plan(&format!(
            r#"{base}[{{"flag":"depth","values":["1mm","1.5mm","1m"]}}]}}"#
        ))
        .unwrap();
        assert_eq!(ok.len(), 3);
    }
}
