//! Headless Chromium, driven over the DevTools protocol (JSON over a WebSocket): open a page,
//! evaluate JavaScript in it, wait for a condition, take a screenshot. Used by
//! `tests/browser.rs` and `benches/view.rs`.
//!
//! Chromium runs as the probe on this kind of machine runs it: `--headless=new`, `--no-sandbox`
//! (needed as root), no background networking (the machine's closed network refuses it), and a
//! fresh profile directory, removed afterwards.

#![allow(dead_code)] // each user needs a different part

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

// Its own copy of the deadline helper, as `benches/view.rs` includes this folder without one;
// the tests that include it (`tests/view.rs`, `tests/browser.rs`) load the same file again.
#[allow(clippy::duplicate_mod)]
#[path = "../deadline/mod.rs"]
mod deadline;

/// How long Chromium may take to start and open its DevTools port.
const STARTUP: Duration = Duration::from_secs(60);

/// The Chromium binary, if one is installed.
pub fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"].iter().find_map(|name| {
        let lookup = format!("command -v {name}");
        let out =
            deadline::output_within(Command::new("sh").args(["-c", &lookup]), format!("`{lookup}` to exit"));
        out.status.success().then(|| PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
    })
}

/// One headless Chromium with one page open.
pub struct Browser {
    child: Child,
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
    session: String,
    next_id: u64,
    profile: PathBuf,
}

impl Browser {
    /// Starts Chromium with a `width × height` window and opens `url`.
    pub fn open(binary: &PathBuf, url: &str, (width, height): (u32, u32)) -> Browser {
        // A profile of its own: two Chromiums sharing one wait on its lock, and the second exits.
        static OPENED: AtomicUsize = AtomicUsize::new(0);
        let opened = OPENED.fetch_add(1, Ordering::SeqCst);
        let profile = std::env::temp_dir().join(format!("raypool-chromium-{}-{opened}", std::process::id()));
        let _ = std::fs::remove_dir_all(&profile);
        let mut child = Command::new(binary)
            .args([
                "--headless=new",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--remote-debugging-port=0",
                &format!("--user-data-dir={}", profile.display()),
                &format!("--window-size={width},{height}"),
                "about:blank",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("chromium starts");
        // Chromium prints its DevTools address on stderr (read on a thread that keeps draining
        // it afterwards); a Chromium that never does is killed after a minute.
        let stderr = BufReader::new(child.stderr.take().unwrap());
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in stderr.lines().map_while(Result::ok) {
                if let Some((_, address)) = line.split_once("DevTools listening on ") {
                    let _ = tx.send(address.trim().to_string());
                }
            }
        });
        let address = match rx.recv_timeout(STARTUP) {
            Ok(address) => address,
            Err(waited) => {
                let _ = child.kill();
                let status = child.wait();
                let why = match waited {
                    RecvTimeoutError::Timeout => format!("within {STARTUP:?}"),
                    RecvTimeoutError::Disconnected => format!("before it exited ({status:?})"),
                };
                panic!("Chromium never printed its DevTools address {why}");
            }
        };
        let (socket, _) = tungstenite::connect(address.as_str()).expect("DevTools WebSocket connects");
        if let MaybeTlsStream::Plain(stream) = socket.get_ref() {
            stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        }
        let mut browser = Browser { child, socket, session: String::new(), next_id: 0, profile };
        let target = browser.call("Target.createTarget", json!({ "url": url }), false);
        let target = target["targetId"].as_str().expect("a target id").to_string();
        let attached =
            browser.call("Target.attachToTarget", json!({ "targetId": target, "flatten": true }), false);
        browser.session = attached["sessionId"].as_str().expect("a session id").to_string();
        browser.call(
            "Emulation.setDeviceMetricsOverride",
            json!({ "width": width, "height": height, "deviceScaleFactor": 1, "mobile": false }),
            true,
        );
        browser
    }

    /// Sends a DevTools command (to the page's session when `on_page`) and returns its result.
    fn call(&mut self, method: &str, params: Value, on_page: bool) -> Value {
        self.next_id += 1;
        let mut message = json!({ "id": self.next_id, "method": method, "params": params });
        if on_page {
            message["sessionId"] = json!(self.session);
        }
        self.socket.send(Message::text(message.to_string())).expect("DevTools accepts a command");
        loop {
            let reply = self.socket.read().expect("DevTools answers");
            let Ok(text) = reply.to_text() else { continue };
            let reply: Value = serde_json::from_str(text).expect("DevTools speaks JSON");
            if reply["id"] == json!(self.next_id) {
                assert!(reply.get("error").is_none(), "{method}: {}", reply["error"]);
                return reply["result"].clone();
            }
        }
    }

    /// The value of the JavaScript expression `expression` in the page.
    pub fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
            true,
        );
        assert!(result.get("exceptionDetails").is_none(), "{expression}: {}", result["exceptionDetails"]);
        result["result"]["value"].clone()
    }

    /// Evaluates `condition` every 50 ms until it is `true` (an exception, say before the
    /// page has loaded, counts as false); panics after `limit`.
    pub fn wait_for(&mut self, condition: &str, limit: Duration) {
        let start = Instant::now();
        let guarded =
            format!("(() => {{ try {{ return !!({condition}); }} catch (e) {{ return false; }} }})()");
        while self.eval(&guarded) != json!(true) {
            assert!(start.elapsed() < limit, "still not true after {limit:?}: {condition}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Drags the mouse with the left button from `from` to `to` (page pixels), in `steps` moves.
    pub fn drag(&mut self, from: (f64, f64), to: (f64, f64), steps: u32) {
        self.mouse("mousePressed", from, 1);
        for k in 1..=steps {
            let t = f64::from(k) / f64::from(steps);
            self.mouse("mouseMoved", (from.0 + (to.0 - from.0) * t, from.1 + (to.1 - from.1) * t), 1);
        }
        self.mouse("mouseReleased", to, 0);
    }

    /// One mouse event of the left button (`mousePressed`, `mouseMoved`, `mouseReleased`) at
    /// `(x, y)` page pixels, with `buttons` held (1: the left one).
    pub fn mouse(&mut self, kind: &str, (x, y): (f64, f64), buttons: u32) {
        let event =
            json!({ "type": kind, "x": x, "y": y, "button": "left", "buttons": buttons, "clickCount": 1 });
        self.call("Input.dispatchMouseEvent", event, true);
    }

    /// Turns the mouse wheel by `delta_y` pixels at `at` (positive: towards the user).
    pub fn wheel(&mut self, (x, y): (f64, f64), delta_y: f64) {
        let event = json!({ "type": "mouseWheel", "x": x, "y": y, "deltaX": 0, "deltaY": delta_y });
        self.call("Input.dispatchMouseEvent", event, true);
    }

    /// The page as it is on screen, PNG.
    pub fn screenshot(&mut self) -> Vec<u8> {
        self.capture(json!({ "format": "png" }))
    }

    /// The rectangle `[x, y, width, height]` (page pixels) of the page as it is on screen, PNG.
    pub fn screenshot_of(&mut self, [x, y, width, height]: [f64; 4]) -> Vec<u8> {
        let clip = json!({ "x": x, "y": y, "width": width, "height": height, "scale": 1 });
        self.capture(json!({ "format": "png", "clip": clip }))
    }

    fn capture(&mut self, params: Value) -> Vec<u8> {
        use base64::Engine as _;
        let shot = self.call("Page.captureScreenshot", params, true);
        base64::engine::general_purpose::STANDARD.decode(shot["data"].as_str().unwrap()).unwrap()
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.profile);
    }
}
