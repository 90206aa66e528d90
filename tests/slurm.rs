//! A real Slurm cluster: `examples/slurm/local-cluster.sh` starts munged, slurmctld and
//! slurmd on this machine; `examples/slurm/submit.sh` submits a job array of shards and a
//! merge job that depends on it; the merged image must equal the one-process render byte for
//! byte, and no daemon may outlive the test, pass or fail.
//!
//! Needs root and Debian's `slurm-wlm` and `munge`. Without them the test says so and skips;
//! under `.ci/run` (which installs them and sets `RAYPOOL_CI=1`) it fails instead.

mod deadline;

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use deadline::output_within;

const REPO: &str = env!("CARGO_MANIFEST_DIR");

fn run(program: &str, args: &[&str], env: &[(&str, &str)]) -> Output {
    let name = Path::new(program).file_name().map_or(program.into(), |n| n.to_string_lossy());
    let what = format!("`{name} {}` to exit", args.first().unwrap_or(&""));
    output_within(Command::new(program).args(args).envs(env.iter().copied()), what)
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

/// Why Slurm cannot run here, if it cannot.
fn missing() -> Option<String> {
    let absent: Vec<&str> = ["munged", "slurmctld", "slurmd", "sbatch", "scontrol"]
        .into_iter()
        .filter(|tool| !run("sh", &["-c", &format!("command -v {tool}")], &[]).status.success())
        .collect();
    if !absent.is_empty() {
        return Some(format!("{} not installed (apt-get install -y slurm-wlm munge)", absent.join(", ")));
    }
    let uid = text(&run("id", &["-u"], &[]));
    (uid.trim() != "0").then(|| "not root (the daemons run as root and munge)".to_string())
}

/// The cluster's daemons; stopped by their pid files when dropped, also when a test fails.
struct Cluster {
    dir: PathBuf,
    conf: String,
}

impl Cluster {
    fn start(dir: &Path) -> Cluster {
        // Two free ports, both held until both are known, so they cannot be the same one.
        let (a, b) = (free_port(), free_port());
        let ports = format!("{} {}", a.local_addr().unwrap().port(), b.local_addr().unwrap().port());
        drop((a, b));
        let script = format!("{REPO}/examples/slurm/local-cluster.sh");
        let out = run(&script, &["start", dir.to_str().unwrap()], &[("SLURM_PORTS", &ports)]);
        let cluster = Cluster { dir: dir.to_owned(), conf: dir.join("slurm.conf").display().to_string() };
        assert!(out.status.success(), "the cluster did not start: {}", text(&out));
        cluster
    }

    fn daemon_pids(&self) -> Vec<(String, u32)> {
        ["slurmd.pid", "slurmctld.pid", "munge/munged.pid"]
            .iter()
            .filter_map(|f| {
                let pid = std::fs::read_to_string(self.dir.join(f)).ok()?.trim().parse().ok()?;
                Some((f.to_string(), pid))
            })
            .collect()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let script = format!("{REPO}/examples/slurm/local-cluster.sh");
        let out = run(&script, &["stop", self.dir.to_str().unwrap()], &[]);
        if !out.status.success() {
            eprintln!("stopping the cluster: {}", text(&out));
        }
    }
}

/// Whether process `pid` exists and is not a zombie (exited, waiting to be reaped).
fn alive(pid: u32) -> bool {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    // The state follows the command name's closing parenthesis.
    stat.rsplit_once(')').is_some_and(|(_, rest)| !rest.trim_start().starts_with('Z'))
}

/// A listener on a port the system chose; the port is free again once it is dropped.
fn free_port() -> TcpListener {
    TcpListener::bind("127.0.0.1:0").unwrap()
}

/// The state of job `id` once it has ended, waiting at most `limit`.
fn wait_for(conf: &str, id: &str, limit: Duration) -> String {
    let start = Instant::now();
    loop {
        let out = text(&run("scontrol", &["show", "job", id], &[("SLURM_CONF", conf)]));
        let state =
            out.split_whitespace().find_map(|w| w.strip_prefix("JobState=")).unwrap_or("").to_string();
        let running = ["PENDING", "RUNNING", "CONFIGURING", "COMPLETING", ""].contains(&state.as_str());
        if !running || start.elapsed() > limit {
            return state;
        }
        std::thread::sleep(Duration::from_millis(500));
    }
}

#[test]
fn a_job_array_of_shards_merges_into_the_one_process_image() {
    if let Some(why) = missing() {
        let required = std::env::var_os("RAYPOOL_CI").is_some();
        assert!(!required, "Slurm is required under .ci/run: {why}");
        deadline::skipped("a_job_array_of_shards_merges_into_the_one_process_image", &why);
        return;
    }
    let dir = std::env::temp_dir().join(format!("raypool-slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let raypool = env!("CARGO_BIN_EXE_raypool");
    let render = ["--scene", "final", "--width", "90", "--spp", "4", "--depth", "12", "--tile", "8"];
    let merged = dir.join("merged.pfm");

    let pids = {
        let cluster = Cluster::start(&dir.join("cluster"));
        let pids = cluster.daemon_pids();
        assert_eq!(pids.len(), 3, "three daemons with pid files: {pids:?}");
        let parts = dir.join("parts").display().to_string();
        let env = [("SLURM_CONF", cluster.conf.as_str()), ("RAYPOOL", raypool), ("PARTS", parts.as_str())];
        let mut args = vec!["5", merged.to_str().unwrap()];
        args.extend_from_slice(&render);
        let out = run(&format!("{REPO}/examples/slurm/submit.sh"), &args, &env);
        assert!(out.status.success(), "sbatch: {}", text(&out));
        let ids = String::from_utf8_lossy(&out.stdout).trim().to_string();
        let (array, merge) = ids.split_once(' ').unwrap_or_else(|| panic!("two job ids, got '{ids}'"));
        let state = wait_for(&cluster.conf, merge, Duration::from_secs(180));
        let log = std::fs::read_to_string(dir.join("parts/merge.log")).unwrap_or_default();
        assert_eq!(state, "COMPLETED", "merge job {merge} after array {array}: {log}");
        assert!(log.contains("merged 5 parts"), "{log}");
        pids
    }; // the cluster stops here

    for (file, pid) in pids {
        assert!(!alive(pid), "{file}'s daemon {pid} still runs after stop");
    }
    let whole = dir.join("whole.pfm");
    let mut args = vec!["render", "--out", whole.to_str().unwrap()];
    args.extend_from_slice(&render);
    assert!(run(raypool, &args, &[]).status.success());
    assert!(std::fs::read(&whole).unwrap() == std::fs::read(&merged).unwrap(), "merged image differs");
    let _ = std::fs::remove_dir_all(&dir);
}
