//! A 3MF package whose part declares more than the memory budget is refused before anything
//! is inflated. Its own test binary: the budget is process-wide, and no other test may run
//! under the small one set here.

use std::io::{Cursor, Write};
use std::path::Path;

use blocksmith_kernel::io::threemf::read_3mf;
use blocksmith_kernel::limits::set_memory_limit;

#[test]
fn a_part_declaring_more_than_the_budget_is_refused_before_inflating() {
    // 64 MiB of spaces deflate to well under 1 MiB; with a budget of 1 MiB the declared size
    // is refused before any inflating.
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let o = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    zip.start_file("3D/3dmodel.model", o).unwrap();
    let spaces = vec![b' '; 1 << 20];
    for _ in 0..64 {
        zip.write_all(&spaces).unwrap();
    }
    let bytes = zip.finish().unwrap().into_inner();
    assert!(bytes.len() < 1 << 20, "{} bytes", bytes.len());
    set_memory_limit(1 << 20);
    let e = read_3mf(&bytes, Path::new("bomb.3mf")).unwrap_err();
    assert!(e.to_string().starts_with("bomb.3mf: malformed 3MF: "), "{e}");
    assert!(e.to_string().contains("declares 67108864 bytes"), "{e}");
}
