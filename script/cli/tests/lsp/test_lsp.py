"""`blocksmith lsp` driven by a real language-server client (pytest-lsp, on pygls), as an
editor drives it: documents opened and changed, diagnostics published, requests answered.
Run by script/cli/tests/lsp.rs with BLOCKSMITH_BIN set to the binary under test."""

import os
import subprocess
from pathlib import Path

import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

BIN = os.environ["BLOCKSMITH_BIN"]


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[BIN, "lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(capabilities=types.ClientCapabilities()))
    yield
    await lsp_client.shutdown_session()


async def open_doc(client: LanguageClient, path: Path, text: str) -> str:
    path.write_text(text)
    uri = path.resolve().as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="rhai", version=1, text=text)
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return uri


def spans(client: LanguageClient, uri: str):
    return {
        d.code: ((d.range.start.line, d.range.start.character), (d.range.end.line, d.range.end.character), d.message)
        for d in client.diagnostics[uri]
    }


async def test_diagnostics_of_each_class_with_their_ranges(client: LanguageClient, tmp_path: Path):
    uri = await open_doc(client, tmp_path / "broken.rhai", "let m = cube(2;\n")
    (code,) = spans(client, uri)
    assert code == "syntax"

    text = (
        'import "chek" as c;\n'                                   # 0: unresolved import
        'let n = param("n", 20, #{ min: 1, max: 12 });\n'         # 1: default out of range
        "let m = cilinder(1, 2, 16);\n"                            # 2: unknown function
        "let k = cube(1);\n"                                       # 3
        "let v = k.volum();\n"                                     # 4: unknown method
        "let s = cylinder(1, 2, 16.5);\n"                          # 5: no signature
        "let e = extrude(rect([0, 0], [1, 1]), 2, #{ twsit: 30 });\n"  # 6: unknown option
        "k.translate([5, 0, 0]);\n"                                # 7: the lint
        "k\n"
    )
    uri = await open_doc(client, tmp_path / "classes.rhai", text)
    found = spans(client, uri)
    assert found["unresolved-import"][:2] == ((0, 7), (0, 13))
    assert 'did you mean "check"' in found["unresolved-import"][2]
    assert found["param-default"][0] == (1, 19)
    assert found["unknown-function"][:2] in [((2, 8), (2, 16)), ((4, 10), (4, 15))]
    messages = [d.message for d in client.diagnostics[uri]]
    assert "unknown function `cilinder` (did you mean `cylinder`?)" in messages
    assert "Mesh has no method `volum` (did you mean `volume`?)" in messages
    assert found["no-signature"][:2] == ((5, 8), (5, 16))
    assert "argument 3 `segments` must be an integer, got a float" in found["no-signature"][2]
    assert found["unknown-option"][:2] == ((6, 44), (6, 49))
    assert "did you mean `twist`" in found["unknown-option"][2]
    assert found["dropped-result"][:2] == ((7, 2), (7, 11))

    # As you type: fixing the name clears its diagnostic.
    fixed = text.replace("cilinder", "cylinder")
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=fixed)],
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    messages = [d.message for d in client.diagnostics[uri]]
    assert not any("cilinder" in m for m in messages)


async def completion(client: LanguageClient, uri: str, line: int, character: int):
    result = await client.text_document_completion_async(
        types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=types.Position(line=line, character=character),
        )
    )
    items = result.items if isinstance(result, types.CompletionList) else result
    return [i.label for i in items]


async def test_completion_after_a_mesh_and_inside_an_option_map(client: LanguageClient, tmp_path: Path):
    text = "let m = cube(2).translate([1, 0, 0]);\nm.\nlet e = extrude(rect([0, 0], [1, 1]), 2, #{ \n"
    uri = await open_doc(client, tmp_path / "complete.rhai", text)
    labels = await completion(client, uri, 1, 2)
    assert {"catmull_clark", "volume", "vertex_count", "translate"} <= set(labels)
    assert "sharp_all" not in labels  # a Block's method, not a Mesh's
    labels = await completion(client, uri, 2, 44)
    assert labels == ["center", "scale", "slices", "twist"]


async def test_hover_is_the_text_of_blocksmith_doc(client: LanguageClient, tmp_path: Path):
    uri = await open_doc(client, tmp_path / "hover.rhai", "let m = cylinder(1, 2, 16);\nm\n")
    hover = await client.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=0, character=10))
    )
    doc = subprocess.run([BIN, "doc", "cylinder"], capture_output=True, text=True, check=True).stdout
    assert hover.contents.value.rstrip("\n") == doc.rstrip("\n")


async def test_definition_leads_into_an_imported_module(client: LanguageClient, tmp_path: Path):
    (tmp_path / "parts.rhai").write_text("/// A table leg.\nfn leg(h) {\n    cube(1).scale([0.1, 0.1, h])\n}\n")
    text = 'import "parts" as p;\nlet l = p::leg(2);\nl\n'
    uri = await open_doc(client, tmp_path / "table.rhai", text)
    assert spans(client, uri) == {}
    result = await client.text_document_definition_async(
        types.DefinitionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=1, character=12))
    )
    location = result[0] if isinstance(result, list) else result
    assert location.uri == (tmp_path / "parts.rhai").resolve().as_uri()
    assert (location.range.start.line, location.range.start.character) == (1, 3)
    labels = await completion(client, uri, 1, 11)
    assert "leg" in labels


async def test_signature_help_symbols_inlay_hints_and_the_run_lens(client: LanguageClient, tmp_path: Path):
    text = 'let n = param("count", 3, #{ min: 1, max: 12, step: 1 });\nfn half(x) { x / 2 }\ncube(2)\n'
    uri = await open_doc(client, tmp_path / "lens.rhai", text)
    doc_id = types.TextDocumentIdentifier(uri=uri)
    help = await client.text_document_signature_help_async(
        types.SignatureHelpParams(text_document=doc_id, position=types.Position(line=2, character=5))
    )
    assert help.signatures[help.active_signature].label.startswith("cube(")
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=doc_id))
    assert [s.name for s in symbols] == ["count", "half"]
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(text_document=doc_id, range=types.Range(start=types.Position(0, 0), end=types.Position(3, 0)))
    )
    assert hints[0].label.startswith(": int, ") and "12" in hints[0].label
    lenses = await client.text_document_code_lens_async(types.CodeLensParams(text_document=doc_id))
    (run,) = [lens for lens in lenses if lens.command.command == "blocksmith.run"]
    shown = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="blocksmith.run", arguments=run.command.arguments)
    )
    # A cube of side 2: closed, manifold, genus 0, volume 8.
    assert shown["line"] == 2
    assert shown["text"].startswith("closed · manifold · genus 0 · volume 8.000000"), shown
    lenses = await client.text_document_code_lens_async(types.CodeLensParams(text_document=doc_id))
    commands = [lens.command.command for lens in lenses]
    assert commands.count("blocksmith.run") == 1 and commands.count("blocksmith.studio") == 1, commands
    # The run's outcome shows above the line it ran to.
    results = [lens for lens in lenses if lens.command.title == shown["text"]]
    assert [lens.range.start.line for lens in results] == [2], lenses
