//! A program embedding the library with its own allocator (this test binary installs no
//! counting allocator): the memory budget still stops a script's data before an allocation
//! fails and aborts the process. Its own binary, since the budget is process-wide.

use blocksmith_kernel::limits;
use blocksmith_script::{limit_data_sizes, new_engine, EngineOptions};

#[test]
fn scripts_growing_data_in_an_embedding_stop_at_the_budget_instead_of_aborting() {
    assert!(limits::heap_in_use().is_none(), "this binary must not count its heap");
    limits::set_memory_limit(512 << 20);
    let engine = new_engine(EngineOptions::default());
    // Rhai's own size limits, from the budget, since the step check cannot count the heap.
    assert_eq!(engine.max_array_size() as u64, (512 << 20) / 64);
    assert_eq!(engine.max_string_size() as u64, 512 << 20);
    for (script, message) in [
        // Doubling at every step: Rhai's size check of the new array.
        ("let a = [0]; loop { a = [a, a]; }", "Size of array"),
        // A map growing by new keys, which Rhai's size checks do not see: the resident memory,
        // read every few thousand steps.
        ("let m = #{}; let i = 0; loop { m[`k${i}`] = [i, i, i, i]; i += 1; }", "is over the memory budget of 512 MiB"),
        // Joining strings: the estimate of `+` before it allocates.
        ("let s = \"x\"; loop { s = s + s; }", "over the memory budget of 512 MiB"),
    ] {
        let err = match *engine.run(script).expect_err(script) {
            // A stop by the step check carries its reason.
            rhai::EvalAltResult::ErrorTerminated(reason, _) => reason.to_string(),
            other => other.to_string(),
        };
        assert!(err.contains(message), "{script}: {err}");
    }
    // A budget raised later gives the next engine room to match.
    limits::set_memory_limit(1 << 30);
    let mut engine = new_engine(EngineOptions::default());
    assert_eq!(engine.max_array_size() as u64, (1 << 30) / 64);
    limit_data_sizes(&mut engine, 1 << 20);
    assert_eq!(engine.max_string_size(), 1 << 20);
}
