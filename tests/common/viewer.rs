//! A `raypool view` server for a test: started on a free port, its address read from the first
//! line of its stdout, and an HTTP agent that returns 4xx answers instead of failing on them.

#![allow(dead_code)] // each user needs a different part

use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use serde_json::Value;

// Its own copy of the deadline helper, as `browser.rs` has (the benches include this folder
// without one).
#[allow(clippy::duplicate_mod)]
#[path = "../deadline/mod.rs"]
mod deadline;

/// A running viewer; killed when dropped.
pub struct Viewer {
    pub child: Child,
    /// `http://127.0.0.1:PORT/`
    pub url: String,
    agent: ureq::Agent,
}

impl Viewer {
    /// `raypool render` of the server's current scene (`/scene.toml`, camera included) with
    /// `flags`, written as `file` (its format from its extension) in a scratch folder; the
    /// file's bytes.
    pub fn cli_render(&self, flags: &[&str], file: &str) -> Vec<u8> {
        // A folder per call: the tests of one binary run at once, in one process.
        static CALLS: AtomicUsize = AtomicUsize::new(0);
        let call = CALLS.fetch_add(1, Ordering::SeqCst);
        let dir = std::env::temp_dir().join(format!("raypool-view-{}-{call}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (status, scene) = self.get("/scene.toml");
        assert_eq!(status, 200);
        let (scene_path, image_path) = (dir.join("scene.toml"), dir.join(file));
        std::fs::write(&scene_path, scene).unwrap();
        let paths = ["--scene-file", scene_path.to_str().unwrap(), "--out", image_path.to_str().unwrap()];
        let out = deadline::output_within(
            Command::new(env!("CARGO_BIN_EXE_raypool")).arg("render").args(paths).args(flags),
            "`raypool render` of the viewer's scene to exit",
        );
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let image = std::fs::read(image_path).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        image
    }

    /// `raypool view --port 0 ARGS…`
    pub fn start(args: &[&str]) -> Viewer {
        let mut child = Command::new(env!("CARGO_BIN_EXE_raypool"))
            .args(["view", "--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("raypool view starts");
        // Read on a thread of its own, so a server that never prints fails the test, not hangs it.
        let stdout = child.stdout.take().unwrap();
        let (line, first_line) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut first = String::new();
            let _ = BufReader::new(stdout).read_line(&mut first);
            let _ = line.send(first);
        });
        let Ok(first) = first_line.recv_timeout(Duration::from_secs(60)) else {
            let _ = child.kill();
            let _ = child.wait();
            panic!("waited 60 s for `raypool view {args:?}` to print its address: it never happened");
        };
        assert!(first.starts_with("http://127.0.0.1:") && first.ends_with("/\n"), "first line: {first:?}");
        let config = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(60)))
            .build();
        Viewer { child, url: first.trim().to_string(), agent: config.into() }
    }

    /// `GET path`: (status, body).
    pub fn get(&self, path: &str) -> (u16, Vec<u8>) {
        let mut response =
            self.agent.get(format!("{}{}", self.url, path.trim_start_matches('/'))).call().unwrap();
        let status = response.status().as_u16();
        (status, response.body_mut().with_config().limit(1 << 30).read_to_vec().unwrap())
    }

    /// `POST path` with `body`: (status, body as text).
    pub fn post(&self, path: &str, body: &[u8]) -> (u16, String) {
        let mut response =
            self.agent.post(format!("{}{}", self.url, path.trim_start_matches('/'))).send(body).unwrap();
        (response.status().as_u16(), response.body_mut().read_to_string().unwrap())
    }

    /// The event stream: each `data:` line as JSON, in order.
    pub fn events(&self) -> impl Iterator<Item = Value> {
        let response = self.agent.get(format!("{}events", self.url)).call().unwrap();
        assert_eq!(response.status().as_u16(), 200);
        let reader = BufReader::new(response.into_body().into_reader());
        reader.lines().map_while(Result::ok).filter_map(|line| {
            line.strip_prefix("data: ").map(|d| serde_json::from_str(d).expect("JSON event"))
        })
    }

    /// Names of the server process's threads (`/proc/PID/task/*/comm`).
    pub fn thread_names(&self) -> Vec<String> {
        let tasks = std::fs::read_dir(format!("/proc/{}/task", self.child.id())).unwrap();
        tasks
            .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("comm")).ok())
            .map(|n| n.trim().to_string())
            .collect()
    }

    /// What the server wrote on stderr (after it has exited).
    pub fn stderr(&mut self) -> String {
        let mut text = String::new();
        self.child.stderr.take().unwrap().read_to_string(&mut text).unwrap();
        text
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Reads `events` until the `done` of render `generation`; returns that render's events.
pub fn until_done(events: &mut impl Iterator<Item = Value>, generation: u64) -> Vec<Value> {
    let mut seen = Vec::new();
    for event in events {
        if event["gen"] == generation {
            let done = event["type"] == "done";
            seen.push(event);
            if done {
                return seen;
            }
        }
    }
    panic!("the event stream ended before render {generation} was done")
}
