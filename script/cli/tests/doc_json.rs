//! `blocksmith doc --format json`, what editors read, run through the binary.

use blocksmith_script::{doc, new_engine, EngineOptions};

/// `blocksmith doc --format json` parses, and lists every registered function with every
/// signature, its parameters' names and types, return type, doc text and examples.
#[test]
fn json_reference_lists_every_function_with_its_signatures() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .args(["doc", "--format", "json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("doc --format json is JSON");
    let functions = json["functions"].as_array().expect("a functions array");
    let engine = new_engine(EngineOptions::default());
    let registered = doc::functions(&engine);
    let listed: Vec<(String, String)> = functions
        .iter()
        .flat_map(|f| {
            let name = f["name"].as_str().unwrap().to_string();
            f["overloads"]
                .as_array()
                .unwrap()
                .iter()
                .map(move |o| (name.clone(), o["signature"].as_str().unwrap().into()))
        })
        .collect();
    let expected: Vec<(String, String)> = registered.iter().map(|o| (o.name.clone(), o.signature())).collect();
    assert_eq!(listed, expected, "every registered overload, in order");
    assert!(registered.len() > 200, "only {} overloads", registered.len());
    // The fields an editor reads, on a function with a receiver.
    let translate = functions.iter().find(|f| f["name"] == "translate").unwrap();
    let on_mesh = translate["overloads"].as_array().unwrap().iter().find(|o| o["receiver"] == "Mesh").unwrap();
    assert_eq!(on_mesh["kind"], "method");
    assert_eq!(on_mesh["params"][0]["type"], "Mesh");
    assert_eq!(on_mesh["returns"], "Mesh");
    assert!(!on_mesh["doc"].as_str().unwrap().is_empty());
    let cube = functions.iter().find(|f| f["name"] == "cube").unwrap();
    assert!(!cube["overloads"][0]["examples"].as_array().unwrap().is_empty(), "{cube}");
    assert_eq!(cube["overloads"][0]["kind"], "function");
    let plus = functions.iter().find(|f| f["name"] == "+").unwrap();
    assert!(plus["overloads"].as_array().unwrap().iter().any(|o| o["signature"] == "+(a: Mesh, b: Mesh) -> Mesh"));
    // The standard library's modules with their functions.
    let check = json["modules"].as_array().unwrap().iter().find(|m| m["name"] == "check").unwrap();
    assert_eq!(check["import"], "import \"check\" as check;");
    assert!(check["functions"].as_array().unwrap().iter().any(|f| f["signature"] == "check::solid(m, genus)"));
}
