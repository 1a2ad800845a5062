//! One studio session: what is shown, the runs that make it, and the pages that follow it.
//!
//! Each page's parameters are its own: a page follows the *variant* for the parameters its
//! address gives (over the session's defaults, `--set`), and one page's controls never change
//! what another shows. A variant keeps its last good model and its last error (formatted as
//! the terminal prints it); a save runs every variant again. Variants live while a page
//! follows them (the defaults' always; a few a tool asked for, [`KEPT_VARIANTS`]).
//!
//! Runs happen on their own thread, one at a time, never on the server's, variants followed
//! by pages first. A request for a run of the variant being run (a save) sets the engine's
//! interrupt (`EngineOptions::interrupt`, the one cancellation switch), as does dropping it,
//! and the run that follows reads the newest state; a superseded run's result, good or bad,
//! is dropped.
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
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::SystemTime;

use serde_json::json;

use super::recipe_lines::{Site, Step};
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
    /// The run's warnings (dropped results, blocks that touch without connecting), formatted
    /// as the terminal prints them.
    pub warnings: Vec<String>,
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
            warnings: scene.warnings,
            message: String::new(),
        };
        model.message = model.describe();
        model
    }

    /// The message that tells a page about the model (its files follow it on the page's
    /// socket; tools fetch them by URL): JSON `{type: "model", version, run_ms, layers: [{name,
    /// url, facts, control?, control_edges?, provenance?}], params, warnings}` (`provenance`: the
    /// URL of a boolean result's view coloured by operand).
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
                if l.provenance.is_some() {
                    layer["provenance"] = json!(format!("/model/{}/{i}.provenance", self.version));
                }
                layer
            })
            .collect();
        json!({
            "type": "model", "version": self.version, "run_ms": self.run_ms, "layers": layers,
            "params": self.params, "warnings": self.warnings,
        })
        .to_string()
    }
}

/// Told the files the latest run read, after every run.
type InputsHook = Box<dyn Fn(&[PathBuf]) + Send>;

/// Told the chain of calls behind a face a page picked (`blocksmith lsp` shows its first line
/// in the editor).
type PickHook = Box<dyn Fn(&[Step]) + Send>;

/// A parameter set: name to value as typed (`--set`, a page's address).
pub type Params = BTreeMap<String, String>;

/// How many variants no page follows (asked for by tools, [`Session::ask`]) are kept, run again
/// on every save; the least recently asked for goes first.
pub const KEPT_VARIANTS: usize = 4;

/// Where a page's messages go; `false` once the page is gone.
type Sink = Box<dyn Fn(&str) -> bool + Send>;

/// A page following a variant.
struct Page {
    id: u64,
    sink: Sink,
}

/// The recipe run with one parameter set, and what it shows.
struct Variant {
    /// The parameters in force: the session's defaults (`--set`) with the page's over them.
    params: Params,
    model: Option<Arc<Model>>,
    error: Option<String>,
    pages: Vec<Page>,
    /// The number of the newest run asked for, and of the newest one finished (shown or
    /// failed); it needs a run while they differ.
    wanted: u64,
    done: u64,
    /// When it was last asked for (a tick of [`State::tick`]).
    used: u64,
}

impl Variant {
    fn new(params: Params) -> Variant {
        Variant { params, model: None, error: None, pages: Vec::new(), wanted: 0, done: 0, used: 0 }
    }

    /// The messages that bring a page up to date with this variant: its parameters, its model,
    /// its error, whether it is running (or about to).
    fn messages(&self, running: bool) -> Vec<String> {
        let mut out = vec![json!({ "type": "params", "values": self.params }).to_string()];
        if let Some(m) = &self.model {
            out.push(m.message().to_string());
        }
        if let Some(e) = &self.error {
            out.push(json!({ "type": "error", "text": e }).to_string());
        }
        if running || self.wanted != self.done {
            out.push(json!({ "type": "running" }).to_string());
        }
        out
    }

    fn broadcast(&mut self, message: &str) {
        self.pages.retain(|p| (p.sink)(message));
    }
}

struct State {
    /// The parameters of a page whose address gives none (`--set`).
    defaults: Params,
    /// The variants: the defaults' first (never dropped), then those pages follow or tools
    /// asked for.
    variants: Vec<Variant>,
    /// The parameters of the variant being run, if any.
    running: Option<Params>,
    /// Whether the run going was interrupted for another variant's (it stays wanted).
    preempted: bool,
    /// The number of the last model shown, of any variant (0: none yet).
    version: u64,
    next_page: u64,
    tick: u64,
    /// The files the latest run read (the recipe, its imports, loaded files).
    inputs: Vec<PathBuf>,
    inputs_hooks: Vec<InputsHook>,
    pick_hooks: Vec<PickHook>,
    /// The files the last finished run wrote, with the stamp each had when it ended.
    written: BTreeMap<PathBuf, Option<Stamp>>,
}

impl State {
    fn new(defaults: Params) -> State {
        State {
            variants: vec![Variant::new(defaults.clone())],
            defaults,
            running: None,
            preempted: false,
            version: 0,
            next_page: 0,
            tick: 0,
            inputs: Vec::new(),
            inputs_hooks: Vec::new(),
            pick_hooks: Vec::new(),
            written: BTreeMap::new(),
        }
    }

    /// The parameters in force for a page whose address gives `given`.
    fn effective(&self, given: &Params) -> Params {
        let mut p = self.defaults.clone();
        p.extend(given.iter().map(|(k, v)| (k.clone(), v.clone())));
        p
    }

    fn find(&self, params: &Params) -> Option<usize> {
        self.variants.iter().position(|v| &v.params == params)
    }

    fn page(&self, id: u64) -> Option<usize> {
        self.variants.iter().position(|v| v.pages.iter().any(|p| p.id == id))
    }
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
    interrupt: Arc<AtomicBool>,
    wake: Mutex<Sender<()>>,
    /// The files the running (or last) run has written so far.
    writes: Writes,
}

impl Session {
    /// A session on `source` whose pages without parameters of their own use `params`
    /// (`--set`), and its runner thread, which makes the first run at once.
    #[must_use]
    pub fn start(source: Source, params: Params) -> Arc<Session> {
        let (wake, woken) = mpsc::channel();
        let session = Arc::new(Session {
            source,
            state: Mutex::new(State::new(params)),
            interrupt: Arc::new(AtomicBool::new(false)),
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
            state: Mutex::new(State::new(Params::new())),
            interrupt: Arc::new(AtomicBool::new(false)),
            wake: Mutex::new(wake),
            writes: Writes::default(),
        })
    }

    fn state(&self) -> MutexGuard<'_, State> {
        // A page thread that panicked cannot leave the state half-written: every update is
        // one assignment.
        self.state.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    fn wake(&self) {
        let _ = self.wake.lock().unwrap_or_else(std::sync::PoisonError::into_inner).send(());
    }

    /// Marks variant `i` as needing a run; a run of it in progress is interrupted, and so is
    /// a run of a variant no page follows (it runs again once nothing else waits).
    fn want(&self, s: &mut State, i: usize) {
        s.variants[i].wanted += 1;
        let Some(running) = &s.running else { return };
        if running == &s.variants[i].params {
            self.interrupt.store(true, Ordering::SeqCst);
        } else if s.find(running).is_none_or(|r| s.variants[r].pages.is_empty()) {
            s.preempted = true;
            self.interrupt.store(true, Ordering::SeqCst);
        }
    }

    /// Asks for a new run of every variant (a save); runs in progress are interrupted.
    pub fn request_run(&self) {
        let mut s = self.state();
        for i in 0..s.variants.len() {
            self.want(&mut s, i);
        }
        drop(s);
        self.wake();
    }

    /// The watcher's news: these files (each one the recipe reads, or one beside it) changed.
    /// Runs again unless every change is a run's own save (see the module documentation).
    pub fn files_changed(&self, paths: &[PathBuf]) {
        let news = {
            let s = self.state();
            let running = s.running.is_some();
            let own = |p: &PathBuf| {
                (running && self.writes.contains(p)) || s.written.get(p).is_some_and(|&stamp| stamp == Stamp::of(p))
            };
            !paths.iter().all(own)
        };
        if news {
            self.request_run();
        }
    }

    /// The variant for a page or tool giving `given`, made (and asked to run) when there is
    /// none; its index.
    fn variant(&self, s: &mut State, given: &Params) -> usize {
        let params = s.effective(given);
        s.tick += 1;
        let tick = s.tick;
        let i = match s.find(&params) {
            Some(i) => i,
            None => {
                s.variants.push(Variant::new(params));
                let i = s.variants.len() - 1;
                self.want(s, i);
                self.wake();
                i
            }
        };
        s.variants[i].used = tick;
        i
    }

    /// Drops the variants no page follows beyond the [`KEPT_VARIANTS`] most recently asked
    /// for (never the defaults'); a dropped one's run is interrupted.
    fn prune(&self, s: &mut State) {
        loop {
            let idle: Vec<usize> = (1..s.variants.len()).filter(|&i| s.variants[i].pages.is_empty()).collect();
            if idle.len() <= KEPT_VARIANTS {
                return;
            }
            let Some(&oldest) = idle.iter().min_by_key(|&&i| s.variants[i].used) else { return };
            let gone = s.variants.remove(oldest);
            if s.running.as_ref() == Some(&gone.params) {
                self.interrupt.store(true, Ordering::SeqCst);
            }
        }
    }

    /// A new page whose address gives the parameters `given`: it follows the variant for
    /// them, receiving through `sink` (`false`: the page is gone) that variant's state at once,
    /// then every update. Returns the page's number (for [`Session::move_page`] and
    /// [`Session::leave`]).
    pub fn join(&self, given: &Params, sink: impl Fn(&str) -> bool + Send + 'static) -> u64 {
        let mut s = self.state();
        s.next_page += 1;
        let id = s.next_page;
        let i = self.variant(&mut s, given);
        let running = s.running.as_ref() == Some(&s.variants[i].params);
        for m in s.variants[i].messages(running) {
            sink(&m);
        }
        s.variants[i].pages.push(Page { id, sink: Box::new(sink) });
        id
    }

    /// Page `id` now gives the parameters `given` (its controls changed): it follows their
    /// variant, which is run if it is new, and is sent that variant's state.
    pub fn move_page(&self, id: u64, given: &Params) {
        let mut s = self.state();
        let Some(from) = s.page(id) else { return };
        let at = s.variants[from].pages.iter().position(|p| p.id == id).unwrap_or(0);
        let page = s.variants[from].pages.remove(at);
        let to = self.variant(&mut s, given);
        let running = s.running.as_ref() == Some(&s.variants[to].params);
        for m in s.variants[to].messages(running) {
            (page.sink)(&m);
        }
        s.variants[to].pages.push(page);
        self.prune(&mut s);
    }

    /// Page `id` is gone.
    pub fn leave(&self, id: u64) {
        let mut s = self.state();
        if let Some(i) = s.page(id) {
            s.variants[i].pages.retain(|p| p.id != id);
        }
        self.prune(&mut s);
    }

    /// A page (for tests and tools) on the defaults' variant, as a channel of its messages.
    #[must_use]
    pub fn follow(&self) -> Receiver<String> {
        let (tx, rx) = mpsc::channel();
        self.join(&Params::new(), move |m| tx.send(m.to_string()).is_ok());
        rx
    }

    /// A tool asks for the variant with `given` (over the defaults): it is made and run when
    /// there is none, and kept (see [`KEPT_VARIANTS`]). Returns the parameters in force.
    pub fn ask(&self, given: &Params) -> Params {
        let mut s = self.state();
        let i = self.variant(&mut s, given);
        let params = s.variants[i].params.clone();
        self.prune(&mut s);
        params
    }

    /// The parameters of the defaults' variant (`--set`).
    #[must_use]
    pub fn params(&self) -> Params {
        self.state().defaults.clone()
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

    /// Calls `hook` with the chain of calls behind each face a page picks (first call first).
    pub fn on_pick(&self, hook: impl Fn(&[Step]) + Send + 'static) {
        self.state().pick_hooks.push(Box::new(hook));
    }

    /// A page picked a face made by `steps` (first call first): tells the pick hooks. Returns
    /// whether any was told (an editor follows the studio).
    pub fn picked(&self, steps: &[Step]) -> bool {
        let s = self.state();
        for hook in &s.pick_hooks {
            hook(steps);
        }
        !s.pick_hooks.is_empty()
    }

    /// Asks every page to light up the faces made by the call written at `site` (an editor's
    /// cursor rests on it): JSON `{type: "highlight", file, line, column}`; each page fetches the
    /// faces of its model (`/model/V/I.faces?...`).
    pub fn highlight(&self, site: &Site) {
        let message =
            json!({ "type": "highlight", "file": site.file, "line": site.line, "column": site.column }).to_string();
        let mut s = self.state();
        for v in &mut s.variants {
            v.broadcast(&message);
        }
    }

    /// The model on show for a page without parameters of its own, if a run has succeeded.
    #[must_use]
    pub fn model(&self) -> Option<Arc<Model>> {
        self.state().variants[0].model.clone()
    }

    /// Model number `version`, of whichever variant, while it is on show.
    #[must_use]
    pub fn model_numbered(&self, version: u64) -> Option<Arc<Model>> {
        let s = self.state();
        s.variants.iter().filter_map(|v| v.model.as_ref()).find(|m| m.version == version).cloned()
    }

    /// The state of the variant for `given` (over the defaults) as one JSON document (for
    /// tools and tests): `{model, error, params, running}`; `model` and `error` are null for a
    /// variant no page or tool asked for.
    #[must_use]
    pub fn snapshot(&self, given: &Params) -> serde_json::Value {
        let s = self.state();
        let params = s.effective(given);
        let Some(v) = s.find(&params).map(|i| &s.variants[i]) else {
            return json!({ "model": null, "error": null, "params": params, "running": false, "known": false });
        };
        let model: Option<serde_json::Value> = v.model.as_ref().and_then(|m| serde_json::from_str(m.message()).ok());
        let running = s.running.as_ref() == Some(&v.params) || v.wanted != v.done;
        json!({ "model": model, "error": v.error, "params": v.params, "running": running, "known": true })
    }

    fn run_loop(&self, woken: &Receiver<()>) {
        while woken.recv().is_ok() {
            while woken.try_recv().is_ok() {}
            // Every variant that needs a run, those pages follow before the others.
            loop {
                let (params, ticket) = {
                    let mut s = self.state();
                    let next = (0..s.variants.len())
                        .filter(|&i| s.variants[i].wanted != s.variants[i].done)
                        .min_by_key(|&i| (s.variants[i].pages.is_empty(), i));
                    let Some(i) = next else { break };
                    self.interrupt.store(false, Ordering::SeqCst);
                    s.preempted = false;
                    self.writes.clear();
                    let v = &mut s.variants[i];
                    v.broadcast(&json!({ "type": "running" }).to_string());
                    let job = (v.params.clone(), v.wanted);
                    s.running = Some(job.0.clone());
                    job
                };
                let (result, inputs) = self.run_once(params.clone());
                let mut s = self.state();
                s.written = self.writes.list().into_iter().map(|p| (p.clone(), Stamp::of(&p))).collect();
                s.running = None;
                let preempted = std::mem::take(&mut s.preempted);
                for hook in &s.inputs_hooks {
                    hook(&inputs);
                }
                s.inputs = inputs;
                let Some(i) = s.find(&params) else { continue }; // dropped meanwhile
                if preempted || s.variants[i].wanted != ticket {
                    continue; // superseded: a newer request is waiting
                }
                s.variants[i].done = ticket;
                let name = self.named(&s, &params);
                match result {
                    Ok(scene) => {
                        let model = Self::show_in(&mut s, i, scene);
                        eprintln!("{name}: shown ({:.0} ms)", model.run_ms);
                        for w in &model.warnings {
                            eprintln!("{w}");
                        }
                    }
                    Err(e) => {
                        eprintln!("{e}");
                        let v = &mut s.variants[i];
                        v.broadcast(&json!({ "type": "error", "text": e.0 }).to_string());
                        v.error = Some(e.0);
                    }
                }
            }
        }
    }

    /// The source's path, with the parameters that differ from the defaults.
    fn named(&self, s: &State, params: &Params) -> String {
        let differ: Vec<String> =
            params.iter().filter(|(k, v)| s.defaults.get(*k) != Some(v)).map(|(k, v)| format!("{k}={v}")).collect();
        let path = self.source.path().display();
        if differ.is_empty() {
            path.to_string()
        } else {
            format!("{path} ({})", differ.join(", "))
        }
    }

    fn show_in(s: &mut State, i: usize, scene: Scene) -> Arc<Model> {
        s.version += 1;
        let model = Arc::new(Model::new(s.version, scene));
        let v = &mut s.variants[i];
        v.model = Some(Arc::clone(&model));
        v.error = None;
        v.broadcast(model.message());
        model
    }

    /// Shows `scene` as the next model on every page without parameters of its own, clearing
    /// any error.
    pub fn show(&self, scene: Scene) -> Arc<Model> {
        Self::show_in(&mut self.state(), 0, scene)
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
                let access = blocksmith_script::access::Access::default().reporting();
                let options = EngineOptions {
                    context: RunContext { params, shown, writes, access: access.clone(), ..RunContext::default() },
                    interrupt: Some(Arc::clone(&self.interrupt)),
                    ..EngineOptions::default()
                };
                let ran = scene::from_recipe_recorded(path, options);
                // The studio's runs only report their saves: say so on the terminal, once per run.
                for path in access.reported() {
                    eprintln!(
                        "note: not written: {} (`blocksmith watch` never writes files; `blocksmith run` does)",
                        blocksmith_script::printable::printable(&path.display().to_string())
                    );
                }
                ran
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
        assert!(session.snapshot(&Params::new())["error"].is_null());
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
        let (tx, rx) = mpsc::channel();
        let page = session.join(&Params::new(), move |m| tx.send(m.to_string()).is_ok());
        next(&rx, "running");
        std::fs::write(&p, "cube(param(\"size\", 1))").unwrap();
        session.move_page(page, &BTreeMap::from([("size".to_string(), "2".to_string())]));
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

    /// A page on `session` whose address gives `given`, and its messages.
    fn page(session: &Session, given: &[(&str, &str)]) -> (u64, Receiver<String>) {
        let (tx, rx) = mpsc::channel();
        let given: Params = given.iter().map(|(k, v)| ((*k).to_string(), (*v).to_string())).collect();
        (session.join(&given, move |m| tx.send(m.to_string()).is_ok()), rx)
    }

    fn volume(m: &serde_json::Value) -> f64 {
        m["layers"][0]["facts"]["volume"].as_f64().unwrap()
    }

    #[test]
    fn each_page_shows_the_model_of_its_own_parameters() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.rhai");
        std::fs::write(&p, "cube(param(\"size\", 1))").unwrap();
        let session = Session::start(Source::Recipe(p.clone()), Params::from([("size".into(), "1".into())]));
        let (_, plain) = page(&session, &[]);
        let (b, three) = page(&session, &[("size", "3")]);
        assert!((volume(&next(&plain, "model")) - 1.0).abs() < 1e-9);
        assert!((volume(&next(&three, "model")) - 27.0).abs() < 1e-9);
        // One page's controls change what it shows, not what the other shows.
        session.move_page(b, &Params::from([("size".into(), "2".into())]));
        assert!((volume(&next(&three, "model")) - 8.0).abs() < 1e-9);
        std::thread::sleep(Duration::from_millis(200));
        let news: Vec<String> = plain.try_iter().collect();
        assert!(news.iter().all(|m| !m.contains("\"model\"")), "{news:?}");
        // A new page without parameters shows the defaults' model at once, not the last one made.
        let (_, fresh) = page(&session, &[]);
        assert!((volume(&next(&fresh, "model")) - 1.0).abs() < 1e-9);
        assert!((volume(&session.snapshot(&Params::new())["model"]) - 1.0).abs() < 1e-9);
        assert!((volume(&session.snapshot(&Params::from([("size".into(), "2".into())]))["model"]) - 8.0).abs() < 1e-9);
        assert_eq!(session.snapshot(&Params::from([("size".into(), "5".into())]))["known"], false);
        // A save runs both again.
        std::fs::write(&p, "cube(param(\"size\", 1)).scale(2)").unwrap();
        session.request_run();
        assert!((volume(&next(&plain, "model")) - 8.0).abs() < 1e-9);
        assert!((volume(&next(&three, "model")) - 64.0).abs() < 1e-9);
    }
}
