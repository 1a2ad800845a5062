#!/usr/bin/env python3
"""Every 3MF file the test suite wrote validates against the 3MF Consortium's XML schemas.

Usage: python validate_3mf.py [--min N] DIR

The model part of each .3mf under DIR (the part `_rels/.rels` names, `3D/3dmodel.model` in ours) is
validated with lxml against the Core schema (namespace .../core/2015/02) and the Materials and
Properties extension's schema (.../material/2015/02), the two namespaces our writer uses. The
schemas are vendored, unchanged, in tests/data/files/schema_3mf (see its README.md for where they
come from); their imports of the W3C `xml.xsd` are pointed at the vendored copy, since the check
must not need the network. Extension elements the schemas allow by `xs:any ... lax` are checked
against the material schema when they are in its namespace, and an element of the core namespace
placed where only other namespaces may stand (a core element under an extension prefix) fails.

One line per failure, then `3mf schema: N passed, N failed`; exit 1 on any failure, or when fewer
than N files (default 1) were found, so the check cannot pass by finding nothing.
"""
import argparse
import pathlib
import posixpath
import sys
import tempfile
import zipfile

from lxml import etree

SCHEMA_DIR = pathlib.Path(__file__).resolve().parent.parent / "tests" / "data" / "files" / "schema_3mf"
XML_XSD_URL = "http://www.w3.org/2001/xml.xsd"
CORE_NS = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
MATERIAL_NS = "http://schemas.microsoft.com/3dmanufacturing/material/2015/02"
MODEL_REL = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"
RELS_NS = "http://schemas.openxmlformats.org/package/2006/relationships"


def load_schema():
    """The core schema with the material schema imported beside it, as one lxml schema. The files
    are copied to a scratch folder with two edits: their `xml.xsd` location made local, and
    `maxOccurs="2147483647"` (the schemas' "any number") written `unbounded`, since libxml2 refuses
    counts of 2^30 and more (the schemas' own notes say the same of xmllint)."""
    scratch = pathlib.Path(tempfile.mkdtemp(prefix="schema_3mf_"))
    for name in ("core_2015_02.xsd", "material_2015_02.xsd", "xml.xsd"):
        text = (SCHEMA_DIR / name).read_text(encoding="utf-8")
        (scratch / name).write_text(text.replace(XML_XSD_URL, "xml.xsd").replace('"2147483647"', '"unbounded"'), encoding="utf-8")
    wrapper = f"""<?xml version="1.0" encoding="UTF-8"?>
<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema" targetNamespace="urn:blocksmith:schema-set">
  <xs:import namespace="{CORE_NS}" schemaLocation="core_2015_02.xsd"/>
  <xs:import namespace="{MATERIAL_NS}" schemaLocation="material_2015_02.xsd"/>
</xs:schema>
"""
    (scratch / "all.xsd").write_text(wrapper, encoding="utf-8")
    return etree.XMLSchema(etree.parse(str(scratch / "all.xsd")))


def model_part(package):
    """The name of the model part: the target of the start part relationship (OPC), else the
    conventional name."""
    try:
        rels = etree.fromstring(package.read("_rels/.rels"))
    except KeyError:
        return "3D/3dmodel.model"
    for rel in rels.iter(f"{{{RELS_NS}}}Relationship"):
        if rel.get("Type") == MODEL_REL:
            return posixpath.normpath(rel.get("Target", "")).lstrip("/")
    return "3D/3dmodel.model"


def problems_of(path, schema):
    """What the schema finds wrong with one file's model part (empty when nothing is)."""
    with zipfile.ZipFile(path) as package:
        name = model_part(package)
        document = etree.fromstring(package.read(name))
    if document.tag != f"{{{CORE_NS}}}model":
        return [f"{name}: root element {document.tag}, not the core namespace's model"]
    problems = []
    if not schema.validate(document):
        problems += [f"{name}:{e.line}: {e.message}" for e in schema.error_log]
    # `xs:any namespace="##other" processContents="lax"` skips what no schema declares: an element
    # of a known namespace that its schema does not declare is a misplaced one.
    declared = {
        CORE_NS: schema_names(SCHEMA_DIR / "core_2015_02.xsd"),
        MATERIAL_NS: schema_names(SCHEMA_DIR / "material_2015_02.xsd"),
    }
    for element in document.iter(etree.Element):
        qname = etree.QName(element)
        if qname.namespace in declared and qname.localname not in declared[qname.namespace]:
            problems.append(
                f"{name}:{element.sourceline}: element {qname.localname} is not declared in {qname.namespace}"
            )
    return problems


_NAMES = {}


def schema_names(xsd):
    """The global element names a schema file declares."""
    if xsd not in _NAMES:
        tree = etree.parse(str(xsd))
        ns = {"xs": "http://www.w3.org/2001/XMLSchema"}
        _NAMES[xsd] = {e.get("name") for e in tree.getroot().findall("xs:element", ns)}
    return _NAMES[xsd]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("root", nargs="?", default="target/test-output")
    parser.add_argument("--min", type=int, default=1, help="fewest .3mf files expected")
    args = parser.parse_args()
    schema = load_schema()
    files = sorted(p for p in pathlib.Path(args.root).rglob("*") if p.suffix.lower() == ".3mf")
    passed = failed = 0
    for path in files:
        try:
            problems = problems_of(path, schema)
        except Exception as error:  # an unreadable package or model part is a failure, with its reason
            problems = [f"unreadable: {error}"]
        if problems:
            failed += 1
            print(f"FAIL {path}: {'; '.join(problems[:5])}")
        else:
            passed += 1
    print(f"3mf schema: {passed} passed, {failed} failed")
    if len(files) < args.min:
        print(f"expected at least {args.min} .3mf files under {args.root}, found {len(files)}", file=sys.stderr)
        return 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
