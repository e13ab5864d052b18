#!/usr/bin/env python3
"""Validates JSON reports against the schemas of docs/schemas/ (jsonschema, draft 2020-12).

Usage: check_schemas.py SCHEMA_DIR REPORT=FILE [REPORT=FILE ...]
  REPORT names the schema (``design`` → SCHEMA_DIR/design.schema.json); FILE is a report ncgear
  wrote (a file or captured ``--json`` stdout).

Every FILE is validated; each one that does not validate is named with the JSON path and message
of its first violation (the violations ordered by path). Every schema of SCHEMA_DIR must be
used by at least one FILE (a schema nothing is checked against is a gap). Exit 1 on any failure.
"""
import json
import pathlib
import sys

import jsonschema


def first_violation(validator, doc):
    """The first violation by JSON path; one of several alternatives (``anyOf``, ``oneOf``)
    named by the deepest violation inside the alternative that came closest."""
    errors = sorted(validator.iter_errors(doc), key=lambda e: [str(p) for p in e.absolute_path])
    return jsonschema.exceptions.best_match(errors[:1]) if errors else None


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    schema_dir = pathlib.Path(argv[1])
    validators = {}
    for path in sorted(schema_dir.glob("*.schema.json")):
        schema = json.loads(path.read_text())
        jsonschema.Draft202012Validator.check_schema(schema)
        validators[path.name[: -len(".schema.json")]] = jsonschema.Draft202012Validator(schema)
    used, failed, checked = set(), 0, 0
    for arg in argv[2:]:
        report, _, file = arg.partition("=")
        if report not in validators:
            print(f"check_schemas: {file}: no schema {report}.schema.json in {schema_dir}")
            failed += 1
            continue
        used.add(report)
        try:
            doc = json.loads(pathlib.Path(file).read_text())
        except (OSError, ValueError) as e:
            print(f"check_schemas: {file}: not read as JSON: {e}")
            failed += 1
            continue
        checked += 1
        error = first_violation(validators[report], doc)
        if error is not None:
            message = error.message
            if len(message) > 300:  # the message quotes the instance first
                message = message[:100] + " … " + message[-200:]
            print(
                f"check_schemas: {file} does not validate against {report}.schema.json: "
                f"at {error.json_path} ({error.validator}): {message}"
            )
            failed += 1
    for report in sorted(set(validators) - used):
        print(f"check_schemas: {report}.schema.json: no report checked against it")
        failed += 1
    if failed:
        print(f"check_schemas: {failed} failure(s), {checked} file(s) read")
        return 1
    print(f"check_schemas: {checked} file(s) valid against {len(validators)} schemas")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
