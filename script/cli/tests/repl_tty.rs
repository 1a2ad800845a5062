//! The REPL on a terminal: `blocksmith repl` runs in a tmux pane (a real pseudo-terminal),
//! keys are typed with send-keys and the screen is read with capture-pane.

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// A tmux server of its own (its own socket), killed when the test ends.
struct Pane {
    socket: String,
}

impl Pane {
    /// `blocksmith repl` in a new 160×50 pane, started in `dir`, on a tmux server named
    /// after `test` (tests run side by side, each on its own server).
    fn start(dir: &Path, test: &str) -> Pane {
        let socket = format!("blocksmith-repl-{test}-{}", std::process::id());
        let pane = Pane { socket };
        let history = dir.join("history");
        let cmd = format!("BLOCKSMITH_HISTORY='{}' '{}' repl", history.display(), env!("CARGO_BIN_EXE_blocksmith"));
        let dir = dir.to_str().unwrap();
        let out = pane.tmux(&["-f", "/dev/null", "new-session", "-d", "-x", "160", "-y", "50", "-c", dir, &cmd]);
        assert!(out.status.success(), "tmux new-session: {}", String::from_utf8_lossy(&out.stderr));
        pane.wait_for("bs>", 1);
        pane
    }

    fn tmux(&self, args: &[&str]) -> Output {
        Command::new("tmux")
            .args(["-L", &self.socket])
            .args(args)
            .output()
            .expect("tmux runs (the REPL's terminal test needs it: apt-get install tmux)")
    }

    fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", "0"];
        args.extend_from_slice(keys);
        assert!(self.tmux(&args).status.success());
    }

    /// Types `text` literally.
    fn type_text(&self, text: &str) {
        assert!(self.tmux(&["send-keys", "-t", "0", "-l", text]).status.success());
    }

    fn screen(&self) -> String {
        String::from_utf8_lossy(&self.tmux(&["capture-pane", "-p", "-t", "0"]).stdout).into_owned()
    }

    /// Waits until `text` is on the screen `count` times (the screen's lines lose their
    /// trailing spaces, so a prompt is `bs>`) (at most 60 s: the first start of a
    /// debug build on a busy machine is slow) and returns the screen.
    fn wait_for(&self, text: &str, count: usize) -> String {
        let start = Instant::now();
        loop {
            let screen = self.screen();
            if screen.matches(text).count() >= count {
                return screen;
            }
            assert!(start.elapsed() < Duration::from_secs(60), "waited for {count}× {text:?}; the screen:\n{screen}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The screen's last line with text (where the cursor is).
    fn last_line(&self) -> String {
        self.screen().lines().rev().find(|l| !l.trim().is_empty()).unwrap_or_default().to_string()
    }

    /// Waits until the last line is `line` and returns the screen.
    fn wait_for_last_line(&self, line: &str) -> String {
        let start = Instant::now();
        while self.last_line().trim_end() != line {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "waited for the line {line:?}; the screen:\n{}",
                self.screen()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        self.screen()
    }
}

impl Drop for Pane {
    fn drop(&mut self) {
        let _ = self.tmux(&["kill-server"]);
    }
}

#[test]
fn completion_knows_the_receivers_type_and_load_paths() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("table.rhai"), "let legs = 4;\ncube(legs)").unwrap();
    std::fs::write(dir.path().join("tabular.txt"), "not a script").unwrap();
    let pane = Pane::start(dir.path(), "completion");

    pane.type_text("let m = cube(1); let b = block([0, 0, 0], [1, 1, 1]);");
    pane.keys(&["Enter"]);
    pane.wait_for("bs>", 2);

    // A unique candidate completes in place: `m.catm` is a Mesh's catmull_clark.
    pane.type_text("m.catm");
    pane.keys(&["Tab"]);
    pane.wait_for_last_line("bs> m.catmull_clark");
    pane.keys(&["C-u"]);

    // Two Tabs list the candidates: a Block's methods, not a Mesh's.
    pane.keys(&["C-l"]);
    pane.type_text("b.s");
    pane.keys(&["Tab"]);
    pane.keys(&["Tab"]);
    let screen = pane.wait_for("subdivide", 1);
    assert!(screen.contains("sharp_all"), "a Block's methods after `b.s`:\n{screen}");
    assert!(!screen.contains("catmull_clark"), "a Mesh method offered on a Block:\n{screen}");
    pane.keys(&["C-u"]);

    // The same prefix on the Mesh lists a Mesh's methods, not a Block's.
    pane.keys(&["C-l"]);
    pane.type_text("m.sharp");
    pane.keys(&["Tab"]);
    pane.keys(&["Tab"]);
    std::thread::sleep(Duration::from_millis(300));
    let screen = pane.screen();
    assert!(!screen.contains("sharp_all"), "a Block method offered on a Mesh:\n{screen}");
    pane.keys(&["C-u"]);

    // `:load` completes script files (not other files).
    pane.keys(&["C-l"]);
    pane.type_text(":load ta");
    pane.keys(&["Tab"]);
    pane.wait_for_last_line("bs> :load table.rhai");
    pane.keys(&["Enter"]);
    pane.wait_for("=> Mesh(8 vertices", 1);
}

#[test]
fn unfinished_entries_continue_at_the_continuation_prompt() {
    let dir = tempfile::tempdir().unwrap();
    let pane = Pane::start(dir.path(), "continuation");
    pane.type_text("fn double(x) {");
    pane.keys(&["Enter"]);
    pane.wait_for_last_line("..>");
    pane.type_text("x * 2");
    pane.keys(&["Enter"]);
    pane.wait_for("..>", 2);
    pane.type_text("}");
    pane.keys(&["Enter"]);
    pane.wait_for("bs>", 2);
    pane.type_text("double(21)");
    pane.keys(&["Enter"]);
    pane.wait_for("=> 42", 1);
    // A multi-line string continues too.
    pane.type_text("let s = `one");
    pane.keys(&["Enter"]);
    pane.wait_for_last_line("..>");
    pane.type_text("two`; s.len()");
    pane.keys(&["Enter"]);
    pane.wait_for("=> 7", 1);
}
