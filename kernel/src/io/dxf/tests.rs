//! The DXF reader on small drawings, malformed and arbitrary bytes.

use super::*;

fn read(s: &str) -> Result<Profile, IoError> {
    read_dxf(s.as_bytes(), Path::new("t.dxf"))
}

/// Regions pass through the engine's 1e-8 grid: areas agree to about 1e-8 of their size.
#[track_caller]
fn near(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b}: difference {}", (a - b).abs());
}

/// A DXF from (code, value) pairs inside an ENTITIES section.
fn entities(pairs: &[(i32, &str)]) -> String {
    let mut s = String::from("0\nSECTION\n2\nENTITIES\n");
    for (c, v) in pairs {
        s += &format!("{c}\n{v}\n");
    }
    s + "0\nENDSEC\n0\nEOF\n"
}

#[test]
fn a_written_profile_reads_back_as_the_same_region() {
    let p = Profile::rect(Vec2::new(0.0, 0.0), Vec2::new(10.0, 8.0))
        .unwrap()
        .difference(&Profile::circle(2.0, 24).unwrap().translate(Vec2::new(5.0, 4.0)).unwrap());
    let back = read(&to_dxf(&p)).unwrap();
    assert_eq!(back.contours().len(), 2);
    near(back.area(), p.area(), 1e-7);
    assert_eq!(back.bounds(), p.bounds());
}

#[test]
fn lines_and_arcs_joined_end_to_end_make_a_slot() {
    // A slot: two lines 10 long and two half circles of radius 1 at their ends, in any order
    // and direction: area 20 + the 64-gon's (each half has 32 segments).
    let dxf = entities(&[
        (0, "LINE"),
        (10, "0"),
        (20, "0"),
        (11, "10"),
        (21, "0"),
        (0, "ARC"),
        (10, "0"),
        (20, "1"),
        (40, "1"),
        (50, "90"),
        (51, "270"),
        (0, "LINE"),
        (10, "0"),
        (20, "2"),
        (11, "10"),
        (21, "2"),
        (0, "ARC"),
        (10, "10"),
        (20, "1"),
        (40, "1"),
        (50, "270"),
        (51, "90"),
    ]);
    let p = read(&dxf).unwrap();
    let n = ARC_SEGMENTS as f64;
    near(p.area(), 20.0 + n / 2.0 * (std::f64::consts::TAU / n).sin(), 1e-7);
}

#[test]
fn an_lwpolyline_with_bulges_and_a_circle_inside_make_a_hole() {
    // A 4×2 rectangle whose right side bulges out in a half circle (bulge 1 = 180°), and a
    // circle of radius 0.5 inside it: even-odd makes the circle a hole.
    let dxf = entities(&[
        (0, "LWPOLYLINE"),
        (90, "4"),
        (70, "1"),
        (10, "0"),
        (20, "0"),
        (10, "4"),
        (20, "0"),
        (42, "1"),
        (10, "4"),
        (20, "2"),
        (10, "0"),
        (20, "2"),
        (0, "CIRCLE"),
        (10, "1"),
        (20, "1"),
        (40, "0.5"),
    ]);
    let p = read(&dxf).unwrap();
    let n = ARC_SEGMENTS as f64;
    let disc = |r: f64| n / 2.0 * r * r * (std::f64::consts::TAU / n).sin();
    near(p.area(), 8.0 + disc(1.0) / 2.0 - disc(0.5), 1e-7);
    assert_eq!(p.contours().len(), 2);
    assert_eq!(p.bounds().unwrap().1.x, 5.0, "the bulge reaches x = 4 + 1");
}

#[test]
fn malformed_files_are_refused_naming_the_line() {
    for (dxf, reason) in [
        ("0\nSECTION\n2\nENTITIES\nxx\nLINE\n", ":5: malformed DXF: group code `xx` is not a number"),
        ("0\nSECTION\n2\nENTITIES\n0\n", "has no value line"),
        (
            &entities(&[(0, "LINE"), (10, "a"), (20, "0"), (11, "1"), (21, "1")]) as &str,
            ":8: malformed DXF: `a` is not a number",
        ),
        (&entities(&[(0, "LINE"), (10, "0"), (20, "0"), (11, "1")]), "LINE has no group 21"),
        (&entities(&[(0, "LINE"), (10, "0"), (20, "0"), (11, "1"), (21, "1")]), "no closed contour"),
        (&entities(&[(0, "CIRCLE"), (10, "1e999"), (20, "0"), (40, "1")]), "not a finite number"),
    ] {
        let e = read(dxf).unwrap_err().to_string();
        assert!(e.contains(reason), "{e}");
    }
}

#[test]
fn arbitrary_bytes_never_panic_or_hang() {
    let p = Profile::circle(1.0, 8).unwrap();
    let mut nested = square(0.0, 0.0, 1.0, 1.0);
    nested.extend(insert("b", 2.0, 0.0, &[(70, "2"), (44, "1.5"), (50, "30")]));
    let spline = owned(&[(0, "SPLINE"), (71, "2"), (40, "0"), (40, "0"), (40, "0"), (40, "1"), (40, "1"), (40, "1")]);
    let spline = [spline, owned(&[(10, "0"), (20, "0"), (10, "1"), (20, "2"), (10, "2"), (20, "0")])].concat();
    let base = with_blocks(&[("b", (0.5, 0.5), square(0.0, 0.0, 1.0, 1.0)), ("c", (0.0, 0.0), spline)], &nested)
        + &to_dxf(&p)
        + &entities(&[
            (0, "LWPOLYLINE"),
            (70, "1"),
            (10, "0"),
            (20, "0"),
            (42, "-2"),
            (10, "3"),
            (20, "0"),
            (10, "3"),
            (20, "3"),
        ]);
    let mut rng = crate::math::SplitMix64::new(0x243f_6a88_85a3_08d3);
    let mut next = || rng.next_u64();
    for round in 0..3000 {
        let mut bytes = base.clone().into_bytes();
        if round % 10 == 0 {
            bytes = (0..(next() % 300))
                .map(|_| b"0123456789.-e\n ABCDEFGHIJKLMNOPQRSTUVWXYZ"[(next() % 40) as usize])
                .collect();
        } else {
            for _ in 0..(1 + next() % 6) {
                let i = (next() as usize) % bytes.len().max(1);
                match next() % 3 {
                    0 => bytes[i] = b"0123456789.-e\n"[(next() % 14) as usize],
                    1 => bytes.truncate(i),
                    _ => bytes.insert(i, (next() % 128) as u8),
                }
                if bytes.is_empty() {
                    break;
                }
            }
        }
        let _ = read_dxf(&bytes, Path::new("fuzz.dxf"));
    }
}

/// Writes `target/peers/profile/plate.{dxf,svg}` (a plate with a bore, a slot and cut-out text) for the peer
/// checks: `ezdxf` reads the DXF back (`kernel/benches/profile_peer.py dxf`), a browser
/// renders the SVG. Run with `--ignored`.
#[test]
#[ignore = "writes sample files for the peers"]
fn write_peer_samples() {
    let plate = Profile::rect(Vec2::new(0.0, 0.0), Vec2::new(40.0, 25.0)).unwrap().fillet(3.0, 32).unwrap();
    let bore = Profile::circle(5.0, 48).unwrap().translate(Vec2::new(12.0, 12.5)).unwrap();
    let slot = Profile::rect(Vec2::new(24.0, 10.0), Vec2::new(34.0, 15.0)).unwrap().fillet(2.4, 32).unwrap();
    let label = crate::profile::text(
        "blocksmith",
        &crate::profile::Font::bundled(),
        &crate::profile::TextOptions::DEFAULT.with_size(3.5),
    )
    .unwrap()
    .translate(Vec2::new(4.0, 3.0))
    .unwrap();
    let p = plate.difference(&bore).difference(&slot).difference(&label);
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/peers/profile");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("plate.dxf"), to_dxf(&p)).unwrap();
    std::fs::write(dir.join("plate.svg"), super::super::svg::to_svg(&p)).unwrap();
    let summary: Vec<String> =
        p.contours().iter().map(|c| format!("{} {:.12}", c.len(), crate::profile::contour_area(c))).collect();
    std::fs::write(dir.join("plate.txt"), summary.join("\n") + "\n").unwrap();
    println!("PROFILE_SAMPLE area={} contours={}", p.area(), p.contours().len());
}

/// A block: its name, base point and (code, value) pairs.
type BlockOf<'a> = (&'a str, (f64, f64), Vec<(i32, String)>);
/// A block with an owned name.
type NamedBlock = (String, (f64, f64), Vec<(i32, String)>);

/// A DXF with a BLOCKS section of `blocks` ((name, base point, (code, value) pairs)) and an
/// ENTITIES section of `pairs`.
fn with_blocks(blocks: &[BlockOf], pairs: &[(i32, String)]) -> String {
    let mut s = String::from("0\nSECTION\n2\nBLOCKS\n");
    for (name, (bx, by), body) in blocks {
        s += &format!("0\nBLOCK\n8\n0\n2\n{name}\n70\n0\n10\n{bx}\n20\n{by}\n30\n0\n");
        for (c, v) in body {
            s += &format!("{c}\n{v}\n");
        }
        s += "0\nENDBLK\n";
    }
    s += "0\nENDSEC\n0\nSECTION\n2\nENTITIES\n";
    for (c, v) in pairs {
        s += &format!("{c}\n{v}\n");
    }
    s + "0\nENDSEC\n0\nEOF\n"
}

/// Owned (code, value) pairs.
fn owned(pairs: &[(i32, &str)]) -> Vec<(i32, String)> {
    pairs.iter().map(|&(c, v)| (c, v.to_string())).collect()
}

/// An INSERT of `name` at (x, y) with extra groups.
fn insert(name: &str, x: f64, y: f64, extra: &[(i32, &str)]) -> Vec<(i32, String)> {
    let mut v = owned(&[(0, "INSERT"), (8, "0"), (2, name)]);
    v.extend([(10, x.to_string()), (20, y.to_string()), (30, "0".to_string())]);
    v.extend(owned(extra));
    v
}

fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<(i32, String)> {
    let mut v = owned(&[(0, "LWPOLYLINE"), (90, "4"), (70, "1")]);
    for (x, y) in [(x0, y0), (x1, y0), (x1, y1), (x0, y1)] {
        v.extend([(10, x.to_string()), (20, y.to_string())]);
    }
    v
}

/// The area of the inscribed [`ARC_SEGMENTS`]-gon of a circle of radius `r`.
fn disc(r: f64) -> f64 {
    let n = ARC_SEGMENTS as f64;
    n / 2.0 * r * r * (std::f64::consts::TAU / n).sin()
}

#[test]
fn inserts_place_blocks_moved_scaled_and_rotated_about_their_base_point() {
    // A hole block: a unit circle drawn at (5, 5) with its base point there. A 20 × 10 plate
    // with the hole placed at (5, 5) and, twice as large, at (15, 5); and a 2 × 1 tab block
    // placed at (30, 0) turned 90°: it covers x 29..30, y 0..2.
    let hole = owned(&[(0, "CIRCLE"), (10, "5"), (20, "5"), (40, "1")]);
    let tab = square(0.0, 0.0, 2.0, 1.0);
    let mut top = square(0.0, 0.0, 20.0, 10.0);
    top.extend(insert("hole", 5.0, 5.0, &[]));
    top.extend(insert("HOLE", 15.0, 5.0, &[(41, "2"), (42, "2")]));
    top.extend(insert("Tab", 30.0, 0.0, &[(50, "90")]));
    let p = read(&with_blocks(&[("Hole", (5.0, 5.0), hole), ("TAB", (0.0, 0.0), tab)], &top)).unwrap();
    assert_eq!(p.contours().len(), 4);
    near(p.area(), 200.0 - disc(1.0) - disc(2.0) + 2.0, 1e-6);
    let (lo, hi) = p.bounds().unwrap();
    assert!(lo.distance(Vec2::new(0.0, 0.0)) < 1e-7 && hi.distance(Vec2::new(30.0, 10.0)) < 1e-7, "{lo} {hi}");
    let tab = p.contours().iter().find(|c| c.iter().all(|q| q.x > 28.0)).expect("the tab");
    let xs = tab.iter().map(|q| q.x).fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    let ys = tab.iter().map(|q| q.y).fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
    near(xs.0, 29.0, 1e-7);
    near(xs.1, 30.0, 1e-7);
    near(ys.1, 2.0, 1e-7);
}

#[test]
fn a_minsert_array_places_columns_and_rows_and_nested_blocks_compose() {
    // A 3 × 2 array of holes, 4 apart in x and 3 in y; the holes are a block placing a block.
    let ring = owned(&[(0, "CIRCLE"), (10, "0"), (20, "0"), (40, "0.5")]);
    let hole = insert("ring", 0.0, 0.0, &[]);
    let mut top = square(-2.0, -2.0, 12.0, 6.0);
    top.extend(insert("hole", 1.0, 1.0, &[(70, "3"), (71, "2"), (44, "4"), (45, "3")]));
    let p = read(&with_blocks(&[("ring", (0.0, 0.0), ring), ("hole", (0.0, 0.0), hole)], &top)).unwrap();
    assert_eq!(p.contours().len(), 7);
    near(p.area(), 14.0 * 8.0 - 6.0 * disc(0.5), 1e-6);
    let centres: Vec<Vec2> =
        p.contours()[1..].iter().map(|c| c.iter().copied().sum::<Vec2>() / c.len() as f64).collect();
    for (cx, cy) in [(1.0, 1.0), (5.0, 1.0), (9.0, 1.0), (1.0, 4.0), (5.0, 4.0), (9.0, 4.0)] {
        assert!(centres.iter().any(|c| c.distance(Vec2::new(cx, cy)) < 1e-6), "a hole at ({cx}, {cy}): {centres:?}");
    }
}

#[test]
fn a_block_that_places_itself_or_another_file_or_expands_too_far_is_refused() {
    let circle = owned(&[(0, "CIRCLE"), (10, "0"), (20, "0"), (40, "1")]);
    // a → b → a.
    let dxf = with_blocks(
        &[("a", (0.0, 0.0), insert("b", 1.0, 0.0, &[])), ("b", (0.0, 0.0), insert("a", 1.0, 0.0, &[]))],
        &insert("a", 0.0, 0.0, &[]),
    );
    let e = read(&dxf).unwrap_err().to_string();
    assert!(e.contains("block `A` places itself (through A → B)"), "{e}");
    // Twelve levels, each placing the next ten times: 10^12 circles, refused before drawing.
    let mut blocks: Vec<NamedBlock> = vec![("L0".into(), (0.0, 0.0), circle.clone())];
    for level in 1..=12 {
        blocks.push((format!("L{level}"), (0.0, 0.0), insert(&format!("L{}", level - 1), 0.0, 0.0, &[(70, "10")])));
    }
    let refs: Vec<BlockOf> = blocks.iter().map(|(n, b, v)| (n.as_str(), *b, v.clone())).collect();
    let started = std::time::Instant::now();
    let e = read(&with_blocks(&refs, &insert("L12", 0.0, 0.0, &[]))).unwrap_err().to_string();
    assert!(e.contains("expand to") && e.contains("more than the 50000000"), "{e}");
    assert!(started.elapsed().as_secs() < 10, "counted, not drawn");
    // An empty block placed 65535 × 65535 times is refused too.
    let e = read(&with_blocks(
        &[("none", (0.0, 0.0), Vec::new())],
        &[square(0.0, 0.0, 1.0, 1.0), insert("none", 0.0, 0.0, &[(70, "65535"), (71, "65535")])].concat(),
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("expand to"), "{e}");
    // An external reference (flag 4) names its file and is not read.
    let xref = "0\nSECTION\n2\nBLOCKS\n0\nBLOCK\n2\nX\n70\n4\n1\n/etc/passwd.dxf\n10\n0\n20\n0\n0\nENDBLK\n0\nENDSEC\n";
    let dxf = xref.to_string() + &entities(&[(0, "INSERT"), (2, "X"), (10, "0"), (20, "0")]);
    let e = read(&dxf).unwrap_err().to_string();
    assert!(e.contains("external reference to `/etc/passwd.dxf`: only this file is read"), "{e}");
    // A block nested 300 deep is refused by depth.
    let deep: Vec<NamedBlock> = (0..300)
        .map(|k| {
            let body = if k == 0 { circle.clone() } else { insert(&format!("D{}", k - 1), 0.0, 0.0, &[]) };
            (format!("D{k}"), (0.0, 0.0), body)
        })
        .collect();
    let refs: Vec<BlockOf> = deep.iter().map(|(n, b, v)| (n.as_str(), *b, v.clone())).collect();
    let e = read(&with_blocks(&refs, &insert("D299", 0.0, 0.0, &[]))).unwrap_err().to_string();
    assert!(e.contains("nested deeper than 256"), "{e}");
}

#[test]
fn an_insert_of_an_undefined_block_and_paper_space_draw_nothing() {
    let mut top = square(0.0, 0.0, 4.0, 4.0);
    top.extend(insert("nowhere", 1.0, 1.0, &[]));
    top.extend(owned(&[(0, "CIRCLE"), (67, "1"), (10, "2"), (20, "2"), (40, "1")]));
    let p = read(&with_blocks(&[], &top)).unwrap();
    assert_eq!(p.contours().len(), 1);
    near(p.area(), 16.0, 1e-7);
}

#[test]
fn splines_and_ellipses_draw_their_curves() {
    // A rational quadratic NURBS unit circle (closed) at (10, 0), a whole ellipse of semi-axes
    // 3 and 1.5 at the origin, and a half ellipse of semi-axes 2 and 1 closed by a line.
    let w = std::f64::consts::FRAC_1_SQRT_2.to_string();
    let mut circle = owned(&[(0, "SPLINE"), (70, "11"), (71, "2"), (72, "12"), (73, "9")]);
    for k in [0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0] {
        circle.push((40, k.to_string()));
    }
    for (i, (x, y)) in [(1., 0.), (1., 1.), (0., 1.), (-1., 1.), (-1., 0.), (-1., -1.), (0., -1.), (1., -1.), (1., 0.)]
        .iter()
        .enumerate()
    {
        circle.extend([(10, (x + 10.0).to_string()), (20, y.to_string()), (30, "0".to_string())]);
        circle.push((41, if i % 2 == 1 { w.clone() } else { "1".to_string() }));
    }
    let ellipse = owned(&[
        (0, "ELLIPSE"),
        (10, "0"),
        (20, "0"),
        (11, "3"),
        (21, "0"),
        (40, "0.5"),
        (41, "0"),
        (42, "6.283185307179586"),
    ]);
    let half = owned(&[
        (0, "ELLIPSE"),
        (10, "0"),
        (20, "-10"),
        (11, "2"),
        (21, "0"),
        (40, "0.5"),
        (41, "0"),
        (42, "3.141592653589793"),
        (0, "LINE"),
        (10, "-2"),
        (20, "-10"),
        (11, "2"),
        (21, "-10"),
    ]);
    let p = read(&with_blocks(&[], &[circle, ellipse, half].concat())).unwrap();
    assert_eq!(p.contours().len(), 3);
    let spline = p.contours().iter().find(|c| c[0].x > 8.0).expect("the spline");
    assert_eq!(spline.len(), 4 * 32, "a quarter turn per span: 32 points");
    assert!(spline.iter().all(|q| (q.distance(Vec2::new(10.0, 0.0)) - 1.0).abs() < 1e-7), "on the circle");
    let n = ARC_SEGMENTS as f64;
    let polygon = |r: f64| n / 2.0 * r * r * (std::f64::consts::TAU / n).sin();
    let spline_area = crate::profile::contour_area(spline).abs();
    near(p.area(), spline_area + 0.5 * polygon(3.0) + 0.5 * polygon(2.0) / 2.0, 1e-6);
    assert!((spline_area - std::f64::consts::PI).abs() < 0.01, "{spline_area}");
}

#[test]
fn a_spline_through_fit_points_and_a_mirrored_arc() {
    // A closed spline given by four fit points passes through each; a circle whose extrusion
    // is -z at OCS (5, 0) lies at x = -5.
    let mut fit = owned(&[(0, "SPLINE"), (70, "1"), (71, "3"), (74, "4")]);
    for (x, y) in [(0, 0), (4, 0), (4, 3), (0, 3)] {
        fit.extend([(11, x.to_string()), (21, y.to_string()), (31, "0".to_string())]);
    }
    let mirrored =
        owned(&[(0, "CIRCLE"), (10, "5"), (20, "0"), (30, "0"), (40, "1"), (210, "0"), (220, "0"), (230, "-1")]);
    let p = read(&with_blocks(&[], &[fit, mirrored].concat())).unwrap();
    assert_eq!(p.contours().len(), 2);
    let curve = p.contours().iter().find(|c| c.iter().all(|q| q.x > -1.0)).expect("the spline");
    for (x, y) in [(0.0, 0.0), (4.0, 0.0), (4.0, 3.0), (0.0, 3.0)] {
        assert!(curve.iter().any(|q| q.distance(Vec2::new(x, y)) < 1e-7), "through ({x}, {y})");
    }
    let circle = p.contours().iter().find(|c| c.iter().all(|q| q.x < -3.0)).expect("the mirrored circle");
    let c = circle.iter().copied().sum::<Vec2>() / circle.len() as f64;
    assert!(c.distance(Vec2::new(-5.0, 0.0)) < 1e-7, "{c}");
    // A spline that cannot be evaluated says why, at its line.
    let e = read(&entities(&[(0, "SPLINE"), (71, "3"), (40, "0"), (10, "0"), (20, "0"), (10, "1"), (20, "1")]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("SPLINE cannot be drawn: it has 2 control points, a degree 3 spline needs 4"), "{e}");
}
