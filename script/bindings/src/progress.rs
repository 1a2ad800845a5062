//! How long kernel work tells the host how far it has come. The bindings never draw anything:
//! a host (the `blocksmith` command draws bars on a terminal) gives an engine a [`Progress`]
//! in its [`crate::EngineOptions`], and the work a script starts reports to it.
//!
//! The progress of the running evaluation is the calling thread's *current* progress, made
//! current at every step of the script as the kernel's cancellation token is
//! (`blocksmith_kernel::limits::make_current`), so an API function reports without being
//! handed anything.

use std::cell::RefCell;
use std::sync::Arc;

/// Where a host shows progress. Implemented by the host (a terminal's bars, a page's spinner).
pub trait ProgressSink: Send + Sync {
    /// Work called `task` (`"mesh"`, `"union"`) starts: `total` units when known (a bar), else
    /// none (a spinner). The task ends when the returned value is dropped.
    fn start(&self, task: &str, total: Option<u64>) -> Box<dyn ProgressTask>;
}

/// One piece of work under way, as the host shows it; it ends when dropped.
pub trait ProgressTask {
    /// `done` units of the total are done.
    fn set(&mut self, done: u64);
}

/// The progress sink of an engine: none by default (nothing is shown). Cloning shares it.
#[derive(Clone, Default)]
pub struct Progress(Option<Arc<dyn ProgressSink>>);

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() { "Progress(shown)" } else { "Progress(none)" })
    }
}

impl Progress {
    /// Progress reported to `sink`.
    #[must_use]
    pub fn new(sink: impl ProgressSink + 'static) -> Progress {
        Progress(Some(Arc::new(sink)))
    }

    /// Whether `self` and `other` are the same sink (or both none).
    fn same(&self, other: &Progress) -> bool {
        match (&self.0, &other.0) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        }
    }
}

thread_local! {
    static CURRENT: RefCell<Progress> = RefCell::new(Progress::default());
}

/// Makes `progress` the calling thread's current progress, unless it already is (called at
/// every step of an evaluation: a pointer comparison).
pub fn make_current(progress: &Progress) {
    CURRENT.with(|c| {
        if !c.borrow().same(progress) {
            *c.borrow_mut() = progress.clone();
        }
    });
}

/// Starts reporting `task` to the calling thread's current progress: a task that shows
/// nothing when there is no sink.
#[must_use]
pub fn start(task: &str, total: Option<u64>) -> Task {
    Task(CURRENT.with(|c| c.borrow().0.clone()).map(|sink| sink.start(task, total)))
}

/// A task under way (see [`start`]); it ends when dropped.
pub struct Task(Option<Box<dyn ProgressTask>>);

impl Task {
    /// `done` units of the total are done.
    pub fn set(&mut self, done: u64) {
        if let Some(t) = &mut self.0 {
            t.set(done);
        }
    }
}

/// A task whose total the work tells as it goes (a kernel operation that reports
/// `(done, total)`): started with that total on its first report — when the total is at least
/// its threshold, so short work shows nothing — and ended when dropped.
pub struct Meter {
    name: &'static str,
    from: u64,
    task: Option<Option<Task>>,
}

impl Meter {
    /// A meter for the task `name`, shown whatever its total.
    #[must_use]
    pub fn new(name: &'static str) -> Meter {
        Meter::at_least(name, 0)
    }

    /// A meter for the task `name`, shown only for a total of `from` units or more.
    #[must_use]
    pub fn at_least(name: &'static str, from: u64) -> Meter {
        Meter { name, from, task: None }
    }

    /// `done` of `total` units are done.
    pub fn update(&mut self, done: u64, total: u64) {
        let (name, from) = (self.name, self.from);
        if let Some(task) = self.task.get_or_insert_with(|| (total >= from).then(|| start(name, Some(total)))) {
            task.set(done);
        }
    }
}

/// Shows as a bar named `name` the progress the kernel reports on this thread while the guard
/// lives ([`blocksmith_kernel::limits::Work`]: the outermost work of the call the guard is
/// made for); nothing when the kernel reports none.
#[must_use = "the bar shows only while the guard lives"]
pub fn bar(name: &'static str) -> blocksmith_kernel::limits::ListenGuard {
    let mut meter = Meter::new(name);
    blocksmith_kernel::limits::listen(move |done, total| meter.update(done, total))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// A sink that writes down what it is told.
    struct Log(Arc<Mutex<Vec<String>>>);
    struct LogTask(Arc<Mutex<Vec<String>>>);

    impl ProgressSink for Log {
        fn start(&self, task: &str, total: Option<u64>) -> Box<dyn ProgressTask> {
            self.0.lock().unwrap().push(format!("start {task} {total:?}"));
            Box::new(LogTask(Arc::clone(&self.0)))
        }
    }
    impl ProgressTask for LogTask {
        fn set(&mut self, done: u64) {
            self.0.lock().unwrap().push(format!("set {done}"));
        }
    }
    impl Drop for LogTask {
        fn drop(&mut self) {
            self.0.lock().unwrap().push("end".into());
        }
    }

    #[test]
    fn a_script_reports_long_work_to_the_sink_of_its_engine_and_nothing_without_one() {
        let log = Arc::new(Mutex::new(Vec::new()));
        let options =
            crate::EngineOptions { progress: Progress::new(Log(Arc::clone(&log))), ..crate::EngineOptions::default() };
        let engine = crate::new_engine(options);
        // A boolean is a task of unknown length (a spinner).
        engine.run("let m = cube(2) - cube(1);").unwrap();
        let seen = log.lock().unwrap().clone();
        assert_eq!(seen, ["start -: evaluating the boolean None", "end"], "{seen:?}");
        // The long kernel operations that know their length show bars: each starts with its
        // total, goes forward, and ends at its total (remesh: 4 steps an iteration; decimate: the
        // 160 triangles of 320 to remove; relax: Taubin's 2 steps an iteration; a growth: its
        // 6 modules; a plant's solid: its tubes, then their union; marching cubes: the blocks).
        for (script, task, total) in [
            ("icosphere(1, 2).remesh(#{edge_length: 0.3, iterations: 2})", "remesh", Some(8)),
            ("icosphere(1, 2).decimate(#{ratio: 0.5})", "decimate", Some(160)),
            ("cube(1).relax(#{iterations: 3})", "relax", Some(6)),
            ("lsystem(#{axiom: \"F[+F]F\"}).grow(0)", "grow", Some(6)),
            ("lsystem(#{axiom: \"F[+F]F\"}).grow(0).to_solid()", "to_solid", None),
            ("lsystem(#{axiom: \"F[+F]F\"}).grow(0).catmull_clark(2)", "catmull_clark", Some(5)),
            ("let v = voxels(64); v.fill_box([2, 2, 2], [60, 60, 60]); v.to_mesh()", "to_mesh: marching cubes", None),
        ] {
            log.lock().unwrap().clear();
            engine.run(script).unwrap_or_else(|e| panic!("{script}: {e}"));
            let seen = log.lock().unwrap().clone();
            let started: Vec<u64> = seen
                .iter()
                .filter_map(|l| l.strip_prefix(&format!("start {task} Some(")))
                .map(|t| t.trim_end_matches(')').parse().unwrap())
                .collect();
            assert_eq!(started.len(), 1, "{script}: one bar: {seen:?}");
            if let Some(total) = total {
                assert_eq!(started[0], total, "{script}: {seen:?}");
            }
            // The bar's own lines: from its start to its end.
            let from = seen.iter().position(|l| l.starts_with(&format!("start {task} "))).unwrap();
            let own = &seen[from..];
            let own = &own[..=own.iter().position(|l| l == "end").unwrap_or(own.len() - 1)];
            let sets: Vec<u64> = own.iter().filter_map(|l| l.strip_prefix("set ")?.parse().ok()).collect();
            assert!(sets.len() >= 2 && sets.windows(2).all(|w| w[0] <= w[1]), "{script}: forward: {seen:?}");
            assert_eq!(sets.last(), Some(&started[0]), "{script}: ends at its total: {seen:?}");
            assert_eq!(own.last().map(String::as_str), Some("end"), "{script}: {seen:?}");
        }
        // Work inside the kernel that reports none (a boolean, the engine's own loops) stays a
        // spinner.
        log.lock().unwrap().clear();
        engine.run("minkowski(cube(1), cube(1))").unwrap();
        assert_eq!(*log.lock().unwrap(), ["start minkowski None", "end"]);
        // An engine without a sink: the same work reports nowhere, and a stale sink is not used.
        log.lock().unwrap().clear();
        crate::new_engine(crate::EngineOptions::default()).run("let m = cube(2) - cube(1);").unwrap();
        assert!(log.lock().unwrap().is_empty());
    }
}
