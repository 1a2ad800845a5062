//! A `blocksmith watch` process for the browser tests that include it
//! (`#[path = "support/studio_watch.rs"] mod studio_watch;`).

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// A `blocksmith watch` process and its page's address, stopped when dropped.
pub struct Watch {
    child: Child,
    pub url: String,
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `blocksmith watch recipe`, once it has printed its address.
pub fn watch(recipe: &Path) -> Watch {
    let mut child =
        Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("watch").arg(recipe).stderr(Stdio::piped()).spawn().unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let Some(line) = lines.by_ref().map_while(Result::ok).find(|l| l.contains("http://")) else {
        let _ = child.kill();
        panic!("no address printed");
    };
    // Keep draining its messages so it never blocks on a full pipe.
    std::thread::spawn(move || lines.for_each(drop));
    let url = format!("http://{}", line.split("http://").nth(1).unwrap().split_whitespace().next().unwrap());
    Watch { child, url }
}
