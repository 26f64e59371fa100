//! A small WebDriver client (the W3C protocol over HTTP/1.1, JSON bodies) for Debian's
//! `chromedriver` driving headless `chromium`: start a session, open a page, run a script, set
//! the window's size, move and press the pointer, take screenshots, read the browser's log;
//! and a static file server on 127.0.0.1 for the page. Only what the browser test uses.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The browser and its driver, where Debian puts them.
pub const CHROMIUM: &str = "/usr/bin/chromium";
pub const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

/// A port nobody listens on now.
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

/// One HTTP/1.1 request to `127.0.0.1:port`: the reply's status and JSON body.
fn http(port: u16, method: &str, path: &str, body: Option<&Value>) -> Result<(u16, Value), String> {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string())?;
    stream
        .set_read_timeout(Some(Duration::from_secs(600)))
        .map_err(|e| e.to_string())?;
    let body = body.map(|b| b.to_string()).unwrap_or_default();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .map_err(|e| e.to_string())?;
    // The head, then as many bytes as it says (chromedriver may keep the connection open).
    let mut reader = BufReader::new(stream);
    let mut head = String::new();
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).map_err(|e| e.to_string())? == 0 || line == "\r\n" {
            break;
        }
        head.push_str(&line);
    }
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .ok_or("no HTTP status")?;
    let header = |name: &str| {
        head.lines().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.trim()
                .eq_ignore_ascii_case(name)
                .then(|| v.trim().to_string())
        })
    };
    let mut body = Vec::new();
    if let Some(length) = header("content-length").and_then(|l| l.parse::<usize>().ok()) {
        body.resize(length, 0);
        reader.read_exact(&mut body).map_err(|e| e.to_string())?;
    } else if header("transfer-encoding").is_some_and(|t| t.eq_ignore_ascii_case("chunked")) {
        loop {
            let mut size = String::new();
            reader.read_line(&mut size).map_err(|e| e.to_string())?;
            let n = usize::from_str_radix(size.trim(), 16).map_err(|e| e.to_string())?;
            let mut chunk = vec![0; n + 2];
            reader.read_exact(&mut chunk).map_err(|e| e.to_string())?;
            if n == 0 {
                break;
            }
            body.extend_from_slice(&chunk[..n]);
        }
    } else {
        reader.read_to_end(&mut body).map_err(|e| e.to_string())?;
    }
    let body = String::from_utf8_lossy(&body);
    let value = serde_json::from_str(&body).map_err(|e| format!("{e}: {body}"))?;
    Ok((status, value))
}

/// A running chromedriver with one headless chromium session.
pub struct Browser {
    driver: Child,
    port: u16,
    session: String,
}

impl Browser {
    /// Starts chromium (headless, its own empty profile, downloads into `downloads`) with
    /// `flags` besides the usual ones.
    pub fn start(flags: &[&str], downloads: &Path) -> Result<Self, String> {
        let port = free_port();
        let driver = Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("{CHROMEDRIVER}: {e}"))?;
        let started = Instant::now();
        while http(port, "GET", "/status", None).is_err() {
            if started.elapsed() > Duration::from_secs(20) {
                return Err("chromedriver did not answer".into());
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let profile = std::env::temp_dir().join(format!("voxcast-chromium-{port}"));
        let mut args: Vec<String> = [
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu-sandbox",
            "--enable-unsafe-swiftshader",
            "--use-angle=swiftshader",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--no-first-run",
            "--mute-audio",
            "--window-size=1400,900",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        args.push(format!("--user-data-dir={}", profile.display()));
        args.extend(flags.iter().map(|s| s.to_string()));
        let capabilities = json!({"capabilities": {"alwaysMatch": {
            "goog:chromeOptions": {"binary": CHROMIUM, "args": args, "prefs": {
                "download.default_directory": downloads,
                "download.prompt_for_download": false,
            }},
            "goog:loggingPrefs": {"browser": "ALL"},
        }}});
        let mut browser = Self {
            driver,
            port,
            session: String::new(),
        };
        let reply = browser.call("POST", "/session", Some(&capabilities))?;
        browser.session = reply["sessionId"]
            .as_str()
            .ok_or_else(|| format!("no session: {reply}"))?
            .to_string();
        Ok(browser)
    }

    fn call(&self, method: &str, path: &str, body: Option<&Value>) -> Result<Value, String> {
        let (status, value) = http(self.port, method, path, body)?;
        let value = value.get("value").cloned().unwrap_or(Value::Null);
        if status >= 400 {
            return Err(format!("{method} {path}: {status} {value}"));
        }
        Ok(value)
    }

    fn session_call(
        &self,
        method: &str,
        path: &str,
        body: Option<&Value>,
    ) -> Result<Value, String> {
        self.call(method, &format!("/session/{}{path}", self.session), body)
    }

    /// Opens `url`.
    pub fn open(&self, url: &str) -> Result<(), String> {
        self.session_call("POST", "/url", Some(&json!({ "url": url })))
            .map(drop)
    }

    /// Runs `script` (a function body; `arguments` holds `args`) and gives its return value.
    pub fn run(&self, script: &str, args: Value) -> Result<Value, String> {
        self.session_call(
            "POST",
            "/execute/sync",
            Some(&json!({ "script": script, "args": args })),
        )
    }

    /// Runs `script` until it returns something other than null or false, or `limit` passes.
    pub fn wait_for(&self, script: &str, limit: Duration) -> Result<Value, String> {
        let started = Instant::now();
        loop {
            let v = self.run(script, json!([]))?;
            if !(v.is_null() || v == Value::Bool(false)) {
                return Ok(v);
            }
            if started.elapsed() > limit {
                return Err(format!("waited {limit:?} for: {script}"));
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// Makes the page's own area (the viewport) `width × height` CSS pixels.
    pub fn set_viewport(&self, width: u32, height: u32) -> Result<(), String> {
        let inner = |b: &Self| -> Result<(i64, i64), String> {
            let v = b.run("return [window.innerWidth, window.innerHeight]", json!([]))?;
            Ok((v[0].as_i64().unwrap_or(0), v[1].as_i64().unwrap_or(0)))
        };
        let rect = self.session_call("GET", "/window/rect", None)?;
        let (outer_w, outer_h) = (
            rect["width"].as_i64().unwrap_or(0),
            rect["height"].as_i64().unwrap_or(0),
        );
        let (w, h) = inner(self)?;
        let body = json!({
            "width": width as i64 + outer_w - w,
            "height": height as i64 + outer_h - h,
        });
        self.session_call("POST", "/window/rect", Some(&body))?;
        let started = Instant::now();
        while inner(self)? != (width as i64, height as i64) {
            if started.elapsed() > Duration::from_secs(10) {
                return Err(format!("the viewport stays {:?}", inner(self)?));
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        Ok(())
    }

    /// A PNG of what the page shows.
    ///
    /// A page busy for seconds in one piece (a large volume made ready) keeps chromedriver
    /// from its renderer for a while ("Timed out receiving message from renderer"): asked
    /// again, three times at most.
    pub fn screenshot(&self) -> Result<Vec<u8>, String> {
        let mut tries = 0;
        loop {
            match self.session_call("GET", "/screenshot", None) {
                Ok(b64) => return decode_base64(b64.as_str().unwrap_or_default()),
                Err(e) if tries < 2 && e.contains("Timed out receiving message from renderer") => {
                    tries += 1;
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Presses the primary button at `from`, moves to each of `through` and releases it there
    /// (page coordinates, CSS pixels); a click when `through` is empty.
    pub fn drag(&self, from: (f64, f64), through: &[(f64, f64)]) -> Result<(), String> {
        let at = |(x, y): (f64, f64), ms: u64| {
            json!({"type": "pointerMove", "duration": ms, "origin": "viewport",
                   "x": x.round() as i64, "y": y.round() as i64})
        };
        let mut actions = vec![
            at(from, 0),
            json!({"type": "pointerDown", "button": 0}),
            json!({"type": "pause", "duration": 50}),
        ];
        for &p in through {
            actions.push(at(p, 60));
        }
        actions.push(json!({"type": "pointerUp", "button": 0}));
        let body = json!({"actions": [{
            "type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"},
            "actions": actions,
        }]});
        self.session_call("POST", "/actions", Some(&body))?;
        self.session_call("DELETE", "/actions", None).map(drop)
    }

    /// The browser's log since the last call: (level, message) pairs.
    pub fn log(&self) -> Result<Vec<(String, String)>, String> {
        let entries = self.session_call("POST", "/se/log", Some(&json!({"type": "browser"})))?;
        Ok(entries
            .as_array()
            .map(|a| {
                a.iter()
                    .map(|e| {
                        (
                            e["level"].as_str().unwrap_or_default().to_string(),
                            e["message"].as_str().unwrap_or_default().to_string(),
                        )
                    })
                    .collect()
            })
            .unwrap_or_default())
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        if !self.session.is_empty() {
            let _ = self.call("DELETE", &format!("/session/{}", self.session), None);
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let digits: Vec<u32> = text
        .bytes()
        .filter(|c| !c.is_ascii_whitespace() && *c != b'=')
        .map(|c| value(c).ok_or("not base64"))
        .collect::<Result<_, _>>()?;
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for group in digits.chunks(4) {
        let n = group
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, d)| n | d << (18 - 6 * i));
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..group.len() - 1]);
    }
    Ok(out)
}

/// A static file server on 127.0.0.1 for `root`, on a thread, until the process ends: what
/// `python3 -m http.server` does for the README's serve command, with the types a browser
/// needs (`application/wasm` lets it compile the module while it downloads).
pub fn serve(root: &Path) -> u16 {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a port");
    let port = listener.local_addr().unwrap().port();
    let root = root.to_path_buf();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let root = root.clone();
            std::thread::spawn(move || answer(stream, &root));
        }
    });
    port
}

fn answer(mut stream: TcpStream, root: &Path) {
    let mut line = String::new();
    let mut reader = BufReader::new(&stream);
    if reader.read_line(&mut line).is_err() {
        return;
    }
    // The rest of the request's head.
    let mut header = String::new();
    while reader.read_line(&mut header).is_ok_and(|n| n > 2) {
        header.clear();
    }
    let path = line.split_whitespace().nth(1).unwrap_or("/");
    let path = path.split('?').next().unwrap_or("/");
    let relative = path.trim_start_matches('/');
    let file: PathBuf = if relative.is_empty() {
        root.join("index.html")
    } else {
        root.join(relative)
    };
    let inside = !relative.split('/').any(|p| p == "..");
    let reply = match std::fs::read(&file) {
        Ok(bytes) if inside => {
            let kind = match file.extension().and_then(|e| e.to_str()) {
                Some("html") => "text/html; charset=utf-8",
                Some("js") => "text/javascript",
                Some("wasm") => "application/wasm",
                Some("json") => "application/json",
                _ => "application/octet-stream",
            };
            (200, kind, bytes)
        }
        _ => (404, "text/plain", b"not found".to_vec()),
    };
    let _ = write!(
        stream,
        "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        reply.0,
        if reply.0 == 200 { "OK" } else { "Not Found" },
        reply.1,
        reply.2.len()
    );
    let _ = stream.write_all(&reply.2);
}
