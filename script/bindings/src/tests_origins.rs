use rhai::Dynamic;

use crate::api::mesh::SharedMesh;
use crate::run::run_recipe;
use crate::EngineOptions;

/// Runs `text` as `recipe.rhai` in a new folder; its value and the script's path.
fn run(text: &str) -> (Dynamic, String, Vec<String>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("recipe.rhai");
    std::fs::write(&path, text).unwrap();
    let run = run_recipe(&path, EngineOptions::default()).unwrap_or_else(|f| panic!("{}", f.error));
    (run.value, path.display().to_string(), run.warnings)
}

fn mesh(value: Dynamic) -> SharedMesh {
    value.try_cast::<SharedMesh>().expect("a mesh")
}

/// The chain of face `f` as `call@line:column`, newest first.
fn chain(m: &SharedMesh, f: u32) -> Vec<String> {
    let part = m.0.face_part(f).expect("the face has a part");
    let origin = part.origin.as_ref().expect("the part has an origin");
    origin.chain().map(|o| format!("{}@{}:{}", o.call, o.span.line, o.span.column)).collect()
}

#[test]
fn every_call_of_a_chain_is_a_step_with_its_line_and_column() {
    let (value, path, _) = run("let a = 2;\nlet m = cube(a)\n    .translate([1, 0, 0]).rotate([0, 0, 1], 90);\nm\n");
    let m = mesh(value);
    for f in 0..m.0.face_count() as u32 {
        assert_eq!(chain(&m, f), ["rotate@3:27", "translate@3:6", "cube@2:9"]);
    }
    let origin = m.0.face_part(0).unwrap().origin.clone().unwrap();
    assert_eq!(origin.first().span.file.as_deref(), Some(path.as_str()), "the file is the script's path");
}

#[test]
fn a_face_exposed_by_a_boolean_keeps_the_line_of_the_operand_that_made_it() {
    let text =
        "let body = cube(2);\nlet pip = uv_sphere(0.5, 16, 8);\nlet die = body - pip.translate([0, 0, 1]);\ndie\n";
    let m = mesh(run(text).0);
    let mut firsts: Vec<String> = (0..m.0.face_count() as u32).map(|f| chain(&m, f).pop().unwrap()).collect();
    firsts.sort();
    firsts.dedup();
    assert_eq!(firsts, ["cube@1:12", "uv_sphere@2:11"]);
    let bite = (0..m.0.face_count() as u32).find(|&f| chain(&m, f).last().unwrap().starts_with("uv_sphere")).unwrap();
    assert_eq!(chain(&m, bite), ["-@3:16", "translate@3:22", "uv_sphere@2:11"]);
}

#[test]
fn arrays_of_meshes_script_functions_and_operators_in_loops_are_marked() {
    let text = "fn part(x) { cube(1).translate([x, 0, 0]) }\n\
                let parts = [part(0), part(2)];\n\
                let all = parts[0];\n\
                for i in 1..2 { all = all + parts[i]; }\n\
                all\n";
    let m = mesh(run(text).0);
    let chains: Vec<Vec<String>> = (0..m.0.face_count() as u32).map(|f| chain(&m, f)).collect();
    // The function's own calls are marked at their lines in its body, then its call site.
    let inside = ["translate@1:22", "cube@1:14"];
    assert!(chains.iter().any(|c| c[..] == ["+@4:27", "part@2:14", inside[0], inside[1]]), "{chains:?}");
    assert!(chains.iter().any(|c| c[..] == ["+@4:27", "part@2:23", inside[0], inside[1]]), "{chains:?}");
}

#[test]
fn calls_inside_functions_and_closures_are_marked_at_their_own_lines() {
    // A bore made in a function, a boss made in a closure: each face leads to the line inside
    // the function or closure, then to where it was called.
    let text = "fn bore(r) {\n    let c = cylinder(r, 3, 16);\n    c\n}\n\
                let boss = |h| cube(h).translate([0, 0, 1]);\n\
                let m = cube(2) - bore(0.5);\n\
                m = m + boss.call(1);\n\
                m\n";
    let m = mesh(run(text).0);
    let chains: Vec<Vec<String>> = (0..m.0.face_count() as u32).map(|f| chain(&m, f)).collect();
    assert!(chains.iter().any(|c| c.ends_with(&["bore@6:19".into(), "cylinder@2:13".into()])), "{chains:?}");
    assert!(chains.iter().any(|c| c.ends_with(&["translate@5:24".into(), "cube@5:16".into()])), "{chains:?}");
    // A `catch (e)` inside a function explains `e` as at the top level.
    let text = "fn caught() { try { cube(1).volum() } catch (e) { return e; } }\ncaught()\n";
    let said = run(text).0.to_string();
    assert!(said.starts_with("Mesh has no"), "{said}");
}

#[test]
fn a_call_handing_back_a_mesh_held_elsewhere_adds_no_step() {
    let m = mesh(run("fn keep(m) { m }\nlet c = cube(1);\nlet d = keep(c);\nd\n").0);
    assert_eq!(chain(&m, 0), ["cube@2:9"]);
}

#[test]
fn marking_keeps_what_the_recipe_means() {
    // A block chain still edits its variable; values other than meshes pass through; the lint
    // still sees the recipe as written.
    let text = "let b = block([0, 0, 0], [1, 1, 1]);\n\
                b.subdivide(\"+z\", 2, 2).sharp_all();\n\
                let n = [1, 2, 3].map(|x| x * 2).len() + 1;\n\
                assert_eq(n, 4);\n\
                let s = `${n} faces`;\n\
                assert_eq(s, \"4 faces\");\n\
                let c = cube(1);\n\
                c.translate([5, 0, 0]);\n\
                let m = blocks();\n\
                m.add(b);\n\
                m.to_mesh()\n";
    let (value, _, warnings) = run(text);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains(":8:"), "the dropped translate, at its line: {warnings:?}");
    let m = mesh(value);
    assert_eq!(chain(&m, 0), ["to_mesh@11:3"]);
    // Subdivided 2 × 2 on +z: more than a cube's six faces' worth of vertices.
    assert!(m.0.vertex_count() > 8);
}

#[test]
fn runs_without_a_file_name_leave_the_file_out() {
    let engine = crate::new_engine(EngineOptions::default());
    let ast = engine.compile("cube(1)").unwrap();
    let value = engine.eval_ast::<Dynamic>(&crate::origins::mark_call_sites(&engine, &ast)).unwrap();
    let m = mesh(value);
    let origin = m.0.face_part(0).unwrap().origin.clone().unwrap();
    assert_eq!((origin.span.file.clone(), origin.span.line, origin.span.column), (None, 1, 1));
}

#[test]
fn compound_assignments_stamp_their_variable_and_arrays_still_grow_in_place() {
    let text = "let m = cube(2);\nm -= cube(1).translate([1, 1, 1]);\nlet a = [];\nfor i in 0..3 { a += [i]; }\nassert_eq(a.len(), 3);\nm\n";
    let m = mesh(run(text).0);
    let chains: Vec<Vec<String>> = (0..m.0.face_count() as u32).map(|f| chain(&m, f)).collect();
    assert!(chains.iter().any(|c| c == &["-@2:3", "cube@1:9"]), "{chains:?}");
    assert!(chains.iter().any(|c| c == &["-@2:3", "translate@2:14", "cube@2:6"]), "{chains:?}");
}

#[test]
fn a_chain_whose_arguments_read_its_variable_still_fails_as_it_would_unmarked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("race.rhai");
    std::fs::write(
        &path,
        "let pm = polar_octahedron();\nlet v = pm.poles()[0];\npm.outgoing(v).map(|h| pm.ends(h)[1])\n",
    )
    .unwrap();
    let failure = run_recipe(&path, EngineOptions::default()).err().expect("the data race is reported");
    assert!(failure.error.0.contains("the variable this call chain starts from"), "{}", failure.error);
}

#[test]
fn a_caught_rhai_error_is_the_explained_message_a_run_prints() {
    let text = "let caught = [];\n\
                try { cube(1).catmull_clark(1.5) } catch (e) { caught.push(e); }\n\
                try { cube(1).volum() } catch (e) { caught.push(e); }\n\
                try { [1, 2][5] } catch (e) { caught.push(e); }\n\
                try { throw #{ error: \"mine\", message: \"kept\" }; } catch (e) { caught.push(e); }\n\
                try { cube(-1) } catch (e) { caught.push(e); }\n\
                try { throw 42; } catch { caught.push(0); }\n\
                caught\n";
    let (value, _, _) = run(text);
    let caught: Vec<String> = value.into_array().unwrap().iter().map(ToString::to_string).collect();
    assert!(caught[0].starts_with("catmull_clark(Mesh, float) matches no signature of `catmull_clark`"), "{caught:?}");
    assert!(caught[0].contains("argument 2 `levels` must be an integer, got a float"), "{caught:?}");
    assert_eq!(caught[1], "Mesh has no method `volum` (did you mean `volume`?)");
    assert!(caught[2].contains("out of bounds"), "{caught:?}");
    // A map a recipe throws, and the script API's own errors, are caught as thrown.
    assert!(caught[3].contains("kept") && caught[3].starts_with("#{"), "{caught:?}");
    assert!(caught[4].starts_with("cube: "), "{caught:?}");
    assert_eq!(caught[5], "0");
}

#[test]
fn calls_that_make_no_mesh_are_left_unmarked() {
    // Arithmetic in a loop costs what it did: `sin` returns a float, `*` only numbers and
    // vectors, and `+` with a literal takes no mesh; `cube`, `translate` and the script's own
    // `part` (which may return anything) are marked, and so is `+` of two meshes.
    let engine = crate::new_engine(EngineOptions::default());
    let text = "fn part() { cube(1) }\n\
                let s = 0.0;\n\
                for i in 0..3 { s += sin(i * 0.001) * 2.0 + 1.0; }\n\
                let v = cube(1).volume();\n\
                part().translate([s, 0, 0]) + cube(2)\n";
    let ast = engine.compile(text).unwrap();
    let marked = crate::origins::mark_call_sites(&engine, &ast);
    // The name each `__made_at` records, by where it is.
    let mut names = Vec::new();
    let mut visit = |path: &[rhai::ASTNode], place: &str| {
        let call = match path.last() {
            Some(
                rhai::ASTNode::Expr(rhai::Expr::FnCall(call, _)) | rhai::ASTNode::Stmt(rhai::Stmt::FnCall(call, _)),
            ) => call,
            _ => return true,
        };
        if let (true, Some(rhai::Expr::StringConstant(name, _))) =
            (call.name == crate::origins::MADE_AT, call.args.get(1))
        {
            names.push(format!("{place}{name}"));
        }
        true
    };
    marked.walk(&mut |path: &[rhai::ASTNode]| visit(path, ""));
    for (.., def) in marked.shared_lib().iter_script_fn_info() {
        let rhai::ScriptFuncPayload::Statements(body) = &def.body;
        for s in body.iter() {
            s.walk(&mut Vec::new(), &mut |path: &[rhai::ASTNode]| visit(path, "in part: "));
        }
    }
    names.sort();
    // `AST::walk` visits the functions' bodies too: `cube` three times (the volume's, `cube(2)`
    // and `part`'s), `part`'s again in its own body.
    assert_eq!(names, ["+", "cube", "cube", "cube", "in part: cube", "part", "translate"]);
    assert_eq!(engine.eval_ast::<Dynamic>(&marked).map(|v| v.is::<SharedMesh>()).ok(), Some(true));
}
