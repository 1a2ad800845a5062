//! One studio session: what is shown (the last good model and the last error), the runs that
//! make it, and the pages that follow it.
//!
//! Runs happen on their own thread, one at a time, never on the server's. A request for a run
//! (a save, new parameters) while one is going sets the engine's interrupt
//! (`EngineOptions::interrupt`, the one cancellation switch), and the run that follows reads
//! the newest state; a superseded run's result, good or bad, is dropped. A failed run keeps
//! the last good model and adds the error, formatted as the terminal prints it.
//!
//! A run's own saves are not edits: the files a run writes are listed as it writes them
//! ([`blocksmith_script::context::Writes`]) and stamped (size, modification time) when it ends. A change
//! the watcher reports ([`Session::files_changed`]) to a file the running run has written is
//! its own (an edit by hand racing the run's save is overwritten by it anyway); one to a file
//! the last run wrote that still has the stamp it left runs nothing. So a recipe that saves a
//! file it also loads, or one in the watched folders, does not run itself again and again,
//! while an edit of that file by hand between runs still runs it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::SystemTime;

use serde_json::json;

use super::scene::{self, Layer, Scene};
use blocksmith_script::context::{RunContext, Writes};
use blocksmith_script::EngineOptions;

/// What a session shows.
#[derive(Clone, Debug)]
pub enum Source {
    /// A recipe, run again on every request.
    Recipe(PathBuf),
    /// A mesh file, read again on every request.
    File(PathBuf),
    /// Values shown from outside ([`Session::show`], the REPL); nothing to run. The path is
    /// the name downloads are given.
    Values(PathBuf),
}

impl Source {
    /// The file behind the source.
    #[must_use]
    pub fn path(&self) -> &std::path::Path {
        match self {
            Source::Recipe(p) | Source::File(p) | Source::Values(p) => p,
        }
    }
}

/// A model on show: its number (counting every successful run) and layers.
#[derive(Debug)]
pub struct Model {
    pub version: u64,
    pub layers: Vec<Layer>,
    pub run_ms: f64,
    /// The recipe's parameters as declared (name, kind, default, value, range, choices, doc).
    pub params: Vec<serde_json::Value>,
    /// The message that tells a page about the model, made once (see [`Model::message`]).
    message: String,
}

impl Model {
    /// Model number `version` of `scene`.
    #[must_use]
    pub fn new(version: u64, scene: Scene) -> Model {
        let mut model = Model {
            version,
            layers: scene.layers,
            run_ms: scene.run_time.as_secs_f64() * 1000.0,
            params: scene.params,
            message: String::new(),
        };
        model.message = model.describe();
        model
    }

    /// The message that tells a page about the model (it fetches each layer's `.glb` by URL):
    /// JSON `{type: "model", version, run_ms, layers: [{name, url, facts, control?,
    /// control_edges?}], params}`.
    #[must_use]
    pub fn message(&self) -> &str {
        &self.message
    }

    fn describe(&self) -> String {
        let layers: Vec<serde_json::Value> = self
            .layers
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let mut layer = json!({
                    "name": l.name,
                    "url": format!("/model/{}/{i}.glb", self.version),
                    "facts": l.facts.json(),
                });
                if let Some(c) = &l.control {
                    layer["control"] = json!(format!("/model/{}/{i}.control", self.version));
                    layer["control_edges"] = json!(c.len() / 6);
                }
                layer
            })
            .collect();
        json!({ "type": "model", "version": self.version, "run_ms": self.run_ms, "layers": layers, "params": self.params })
            .to_string()
    }
}

/// Told the files the latest run read, after every run.
type InputsHook = Box<dyn Fn(&[PathBuf]) + Send>;

#[derive(Default)]
struct State {
    model: Option<Arc<Model>>,
    /// The number of the last model shown (0: none yet).
    version: u64,
    error: Option<String>,
    params: BTreeMap<String, String>,
    pages: Vec<Sender<String>>,
    /// The files the latest run read (the recipe, its imports, loaded files).
    inputs: Vec<PathBuf>,
    inputs_hooks: Vec<InputsHook>,
    /// The files the last finished run wrote, with the stamp each had when it ended.
    written: BTreeMap<PathBuf, Option<Stamp>>,
}

/// What tells one version of a file from another without reading it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
}

impl Stamp {
    /// The stamp of the file at `path`, `None` when there is none.
    #[must_use]
    pub fn of(path: &Path) -> Option<Stamp> {
        let m = std::fs::metadata(path).ok()?;
        Some(Stamp { len: m.len(), modified: m.modified().ok() })
    }
}

/// A studio session, shared by the server, the watcher and the runner.
pub struct Session {
    pub source: Source,
    state: Mutex<State>,
    /// Counts run requests; a run whose count is no longer the newest is superseded.
    requested: AtomicU64,
    interrupt: Arc<AtomicBool>,
    /// Whether a run is going; changed with the state locked.
    running: AtomicBool,
    wake: Mutex<Sender<()>>,
    /// The files the running (or last) run has written so far.
    writes: Writes,
}

impl Session {
    /// A session on `source` with `params` (`--set`), and its runner thread, which makes the
    /// first run at once.
    #[must_use]
    pub fn start(source: Source, params: BTreeMap<String, String>) -> Arc<Session> {
        let (wake, woken) = mpsc::channel();
        let session = Arc::new(Session {
            source,
            state: Mutex::new(State { params, ..State::default() }),
            requested: AtomicU64::new(0),
            interrupt: Arc::new(AtomicBool::new(false)),
            running: AtomicBool::new(false),
            wake: Mutex::new(wake),
            writes: Writes::default(),
        });
        let runner = Arc::clone(&session);
        std::thread::spawn(move || runner.run_loop(&woken));
        session.request_run();
        session
    }

    /// A session showing only what is given to [`Session::show`] (the REPL's `:show`), named
    /// `name`; it runs nothing.
    #[must_use]
    pub fn for_values(name: &str) -> Arc<Session> {
        let (wake, _) = mpsc::channel();
        Arc::new(Session {
            source: Source::Values(PathBuf::from(name)),
            state: Mutex::new(State::default()),
            requested: AtomicU64::new(0),
            interrupt: Arc::new(AtomicBool::new(false)),
            running: AtomicBool::new(false),
            wake: Mutex::new(wake),
            writes: Writes::default(),
        })
    }

    fn state(&self) -> MutexGuard<'_, State> {
        // A page thread that panicked cannot leave the state half-written: every update is
        // one assignment.
        self.state.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Asks for a new run; a run in progress is interrupted.
    pub fn request_run(&self) {
        self.requested.fetch_add(1, Ordering::SeqCst);
        if self.running.load(Ordering::SeqCst) {
            self.interrupt.store(true, Ordering::SeqCst);
        }
        let _ = self.wake.lock().unwrap_or_else(std::sync::PoisonError::into_inner).send(());
    }

    /// The watcher's news: these files (each one the recipe reads, or one beside it) changed.
    /// Runs again unless every change is a run's own save (see the module documentation).
    pub fn files_changed(&self, paths: &[PathBuf]) {
        let news = {
            let s = self.state();
            let running = self.running.load(Ordering::SeqCst);
            let own = |p: &PathBuf| {
                (running && self.writes.contains(p)) || s.written.get(p).is_some_and(|&stamp| stamp == Stamp::of(p))
            };
            !paths.iter().all(own)
        };
        if news {
            self.request_run();
        }
    }

    /// Sets the parameters (all of them; those not given fall back to the recipe's defaults)
    /// and runs again when they changed.
    pub fn set_params(&self, params: BTreeMap<String, String>) {
        let changed = {
            let mut s = self.state();
            let changed = s.params != params;
            s.params = params;
            changed
        };
        if changed {
            self.request_run();
        }
    }

    /// The parameters in force.
    #[must_use]
    pub fn params(&self) -> BTreeMap<String, String> {
        self.state().params.clone()
    }

    /// Calls `hook` with the files the latest run read (the recipe, imported modules, loaded
    /// files), now if a run has finished and after every run.
    pub fn on_inputs(&self, hook: impl Fn(&[PathBuf]) + Send + 'static) {
        let mut s = self.state();
        if !s.inputs.is_empty() {
            hook(&s.inputs);
        }
        s.inputs_hooks.push(Box::new(hook));
    }

    /// The model on show, if a run has succeeded.
    #[must_use]
    pub fn model(&self) -> Option<Arc<Model>> {
        self.state().model.clone()
    }

    /// A new page: it receives the messages of the current state at once, then every update.
    #[must_use]
    pub fn follow(&self) -> Receiver<String> {
        let (tx, rx) = mpsc::channel();
        let mut s = self.state();
        for m in Self::state_messages(&s) {
            let _ = tx.send(m);
        }
        s.pages.push(tx);
        rx
    }

    fn state_messages(s: &State) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(m) = &s.model {
            out.push(m.message().to_string());
        }
        out.push(json!({ "type": "params", "values": s.params }).to_string());
        if let Some(e) = &s.error {
            out.push(json!({ "type": "error", "text": e }).to_string());
        }
        out
    }

    /// The current state as one JSON document (for tools and tests).
    #[must_use]
    pub fn snapshot(&self) -> serde_json::Value {
        let s = self.state();
        let model: Option<serde_json::Value> = s.model.as_ref().and_then(|m| serde_json::from_str(m.message()).ok());
        json!({ "model": model, "error": s.error, "params": s.params })
    }

    fn broadcast(s: &mut State, message: &str) {
        s.pages.retain(|p| p.send(message.to_string()).is_ok());
    }

    fn run_loop(&self, woken: &Receiver<()>) {
        while woken.recv().is_ok() {
            while woken.try_recv().is_ok() {}
            let ticket = self.requested.load(Ordering::SeqCst);
            self.interrupt.store(false, Ordering::SeqCst);
            let params = {
                let mut s = self.state();
                self.writes.clear();
                self.running.store(true, Ordering::SeqCst);
                Self::broadcast(&mut s, &json!({ "type": "running" }).to_string());
                s.params.clone()
            };
            let (result, inputs) = self.run_once(params);
            {
                let mut s = self.state();
                s.written = self.writes.list().into_iter().map(|p| (p.clone(), Stamp::of(&p))).collect();
                self.running.store(false, Ordering::SeqCst);
                for hook in &s.inputs_hooks {
                    hook(&inputs);
                }
                s.inputs = inputs;
            }
            if self.requested.load(Ordering::SeqCst) != ticket {
                continue; // superseded: a newer request is waiting
            }
            match result {
                Ok(scene) => {
                    let model = self.show(scene);
                    eprintln!("{}: shown ({:.0} ms)", self.source.path().display(), model.run_ms);
                }
                Err(e) => {
                    eprintln!("{e}");
                    let mut s = self.state();
                    Self::broadcast(&mut s, &json!({ "type": "error", "text": e.0 }).to_string());
                    s.error = Some(e.0);
                }
            }
        }
    }

    /// Shows `scene` as the next model on every page, clearing any error.
    pub fn show(&self, scene: Scene) -> Arc<Model> {
        let mut s = self.state();
        s.version += 1;
        let model = Arc::new(Model::new(s.version, scene));
        s.model = Some(Arc::clone(&model));
        s.error = None;
        Self::broadcast(&mut s, model.message());
        model
    }

    /// One run, and the files it read.
    fn run_once(
        &self,
        params: BTreeMap<String, String>,
    ) -> (Result<Scene, blocksmith_script::run::RunError>, Vec<PathBuf>) {
        match &self.source {
            Source::Recipe(path) => {
                let shown = Some(blocksmith_script::context::Shown::default());
                let writes = Some(self.writes.clone());
                let options = EngineOptions {
                    context: RunContext { params, shown, writes, ..RunContext::default() },
                    interrupt: Some(Arc::clone(&self.interrupt)),
                    ..EngineOptions::default()
                };
                scene::from_recipe_recorded(path, options)
            }
            Source::File(path) => {
                // A .gltf's buffers and images are the model too.
                let gltf = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf"));
                let referenced = if gltf {
                    [
                        blocksmith_script::gltf_buffers::buffer_files(path),
                        blocksmith_script::gltf_buffers::image_files(path),
                    ]
                    .concat()
                } else {
                    Vec::new()
                };
                let read = std::iter::once(path.clone())
                    .chain(referenced)
                    .map(|p| std::fs::canonicalize(&p).unwrap_or(p))
                    .collect();
                (scene::load_file(path), read)
            }
            Source::Values(_) => (Err(blocksmith_script::run::RunError("error: nothing to run".into())), Vec::new()),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    /// The next message of `type` within 30 s (debug builds run recipes slowly).
    fn next(rx: &Receiver<String>, kind: &str) -> serde_json::Value {
        loop {
            let m = rx.recv_timeout(Duration::from_secs(30)).expect("a message");
            let v: serde_json::Value = serde_json::from_str(&m).unwrap();
            if v["type"] == kind {
                return v;
            }
        }
    }

    #[test]
    fn a_failed_run_keeps_the_model_and_a_fixed_one_clears_the_error() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.rhai");
        std::fs::write(&p, "cube(1)").unwrap();
        let session = Session::start(Source::Recipe(p.clone()), BTreeMap::new());
        let rx = session.follow();
        let m = next(&rx, "model");
        assert_eq!(m["layers"][0]["facts"]["triangles"], 12);
        std::fs::write(&p, "let x = ;\ncube(1)").unwrap();
        session.request_run();
        let e = next(&rx, "error");
        assert!(e["text"].as_str().unwrap().contains("r.rhai:1:"), "{e}");
        assert_eq!(session.model().unwrap().version, 1, "the last good model stays");
        std::fs::write(&p, "icosphere(1, 1)").unwrap();
        session.request_run();
        let m = next(&rx, "model");
        assert_eq!((m["version"].as_u64(), m["layers"][0]["facts"]["triangles"].as_u64()), (Some(2), Some(80)));
        assert!(session.snapshot()["error"].is_null());
    }

    #[test]
    fn values_shown_by_the_recipe_follow_its_model_as_layers() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.rhai");
        std::fs::write(&p, "show(cube(1));\nshow([cube(2)]);\nicosphere(1, 1)").unwrap();
        let session = Session::start(Source::Recipe(p), BTreeMap::new());
        let m = next(&session.follow(), "model");
        let layers: Vec<(&str, u64)> = m["layers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| (l["name"].as_str().unwrap(), l["facts"]["triangles"].as_u64().unwrap()))
            .collect();
        assert_eq!(layers, [("model", 80), ("show 1", 12), ("show 2 [0]", 12)]);
    }

    #[test]
    fn a_request_during_a_long_run_interrupts_it_and_only_the_newest_is_shown() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.rhai");
        std::fs::write(&p, "let n = 0; while true { n += 1; }").unwrap();
        let session = Session::start(Source::Recipe(p.clone()), BTreeMap::new());
        let rx = session.follow();
        next(&rx, "running");
        std::fs::write(&p, "cube(param(\"size\", 1))").unwrap();
        session.set_params(BTreeMap::from([("size".to_string(), "2".to_string())]));
        // The first run may read the new recipe before the parameters arrive (the "running"
        // message comes before it reads the file) and show size 1; what must never be shown is
        // the interrupted run, and the parameters' run must follow.
        let m = loop {
            let v: serde_json::Value =
                serde_json::from_str(&rx.recv_timeout(Duration::from_secs(30)).unwrap()).unwrap();
            assert_ne!(v["type"], "error", "the interrupted run is dropped, not shown: {v}");
            if v["type"] == "model" && v["params"][0]["value"].as_i64() == Some(2) {
                break v;
            }
        };
        assert!(m["version"].as_u64().is_some_and(|v| v <= 2), "one model per finished request: {m}");
        assert_eq!(m["params"][0]["name"].as_str(), Some("size"));
        assert!((m["layers"][0]["facts"]["volume"].as_f64().unwrap() - 8.0).abs() < 1e-9);
    }
}
