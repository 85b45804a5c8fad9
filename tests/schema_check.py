#!/usr/bin/env python3
"""The notation's JSON Schema (`statepack schema`) against the files the packer judges.

Every notation the packer accepts (the valid corpus, the states, the test data it packs, the whole-document
```json examples of docs/notation.md) must validate; every invalid corpus file the packer rejects for an
unknown key or an unknown enum value must not. The schema and the reader share their key and enum
tables, so this checks the parts the tables do not: value types and object nesting.

Usage: schema_check.py <statepack executable> <source dir>
"""
import glob
import json
import os
import re
import subprocess
import sys

import jsonschema


def main():
    statepack, src = sys.argv[1], sys.argv[2]
    schema = json.loads(subprocess.run([statepack, "schema"], check=True, capture_output=True, text=True).stdout)
    jsonschema.Draft7Validator.check_schema(schema)
    validator = jsonschema.Draft7Validator(schema)
    failures = []

    # Every $ref names a definition, and every enum lists names (a property pointing at a missing object
    # or an empty table would accept or reject everything silently).
    def walk(node, where):
        if isinstance(node, dict):
            ref = node.get("$ref")
            if ref is not None and ref.removeprefix("#/definitions/") not in schema["definitions"]:
                failures.append(f"{where}: $ref {ref} names no definition")
            if "enum" in node and not node["enum"]:
                failures.append(f"{where}: an empty enum")
            for key, value in node.items():
                walk(value, f"{where}/{key}")
        elif isinstance(node, list):
            for i, value in enumerate(node):
                walk(value, f"{where}/{i}")
    walk(schema, "schema")

    valid = sorted(glob.glob(f"{src}/tests/corpus/valid/**/*.json", recursive=True) + glob.glob(f"{src}/states/*.json")
                   + glob.glob(f"{src}/tests/corpus/warnings/*.json")
                   + [f for f in glob.glob(f"{src}/tests/data/*/*.json") if "/pinned/" not in f])
    documents = [(os.path.relpath(f, src), json.load(open(f, encoding="utf-8"))) for f in valid]
    text = open(f"{src}/docs/notation.md", encoding="utf-8").read()
    for n, block in enumerate(re.findall(r"^```json\n(.*?)^```", text, re.S | re.M), 1):
        if block.lstrip().startswith("{"):
            documents.append((f"docs/notation.md example {n}", json.loads(block)))
    for name, document in documents:
        errors = list(validator.iter_errors(document))
        for e in errors[:3]:
            failures.append(f"{name}: valid notation fails the schema at /{'/'.join(map(str, e.absolute_path))}: "
                            f"{e.message[:200]}")

    # Rejected by the packer for an unknown key or value: the schema must reject them too.
    unknown = re.compile(r"error: unknown [^']*'")
    invalid = [f"{src}/tests/data/unknown_keys.json"]
    for expected in sorted(glob.glob(f"{src}/tests/corpus/invalid/*.expected")):
        if unknown.search(open(expected, encoding="utf-8").read()):
            invalid.append(expected[: -len(".expected")] + ".json")
    for f in invalid:
        if validator.is_valid(json.load(open(f, encoding="utf-8"))):
            failures.append(f"{os.path.relpath(f, src)}: the packer rejects an unknown key or value, the schema accepts it")

    print(f"schema_check: {len(documents)} valid documents, {len(invalid)} invalid ones")
    for f in failures:
        print("FAIL", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
