#!/usr/bin/python3
"""Validate suite result files against a JSON Schema.

Usage: validate_result.py SCHEMA FILE...
       validate_result.py --by-kind SCHEMA_DIR FILE...

With --by-kind each file is checked against the schema of its own kind (its top-level "kind";
none: a run's result file), as KIND_SCHEMAS below maps them; a file of a kind with no schema is
invalid, so that a new kind of file cannot go unchecked.

Prints one line per violation, "FILE: $.json.path: message", and a summary line per file.
Exit status: 0 all files valid, 1 at least one file invalid or unreadable, 2 usage error
(wrong arguments, or a schema that cannot be read or is not itself a valid schema).

Needs the jsonschema package (Debian: python3-jsonschema, 4.x); run it with /usr/bin/python3.
The validator class follows the schema's "$schema" (draft 2020-12 for results/schema/v1.json).
"""

import json
import sys


# Each kind of file the suite writes, by its top-level "kind", and the schema in results/schema/
# that describes it. None: no "kind", a run's result file (suite --out, the suite-mpi file).
KIND_SCHEMAS = {
    None: "v1.json",
    "suite-roofline": "roofline-v1.json",
    "suite-roofline-placement": "roofline-v1.json",
}


def usage(message):
    print(f"validate_result.py: {message}", file=sys.stderr)
    print("usage: validate_result.py SCHEMA FILE... | --by-kind SCHEMA_DIR FILE...", file=sys.stderr)
    return 2


def error_path(error):
    # jsonschema >= 4.0 has ValidationError.json_path; build it by hand for older ones.
    path = getattr(error, "json_path", None)
    if path is not None:
        return path
    out = "$"
    for part in error.absolute_path:
        out += f"[{part}]" if isinstance(part, int) else f".{part}"
    return out


def main(argv):
    if len(argv) < 3 or argv[1] in ("-h", "--help"):
        return usage("need a schema and at least one file")
    try:
        import jsonschema
        from jsonschema.validators import validator_for
    except ImportError:
        return usage(f"the jsonschema module is missing for {sys.executable} (install python3-jsonschema)")

    by_kind = argv[1] == "--by-kind"
    if by_kind and len(argv) < 4:
        return usage("need a schema directory and at least one file")
    validators = {}

    def validator_of(schema_path):
        if schema_path not in validators:
            try:
                with open(schema_path, encoding="utf-8") as f:
                    schema = json.load(f)
            except (OSError, ValueError) as e:
                raise SystemExit(usage(f"cannot read schema {schema_path}: {e}"))
            cls = validator_for(schema, default=jsonschema.Draft202012Validator)
            try:
                cls.check_schema(schema)
            except jsonschema.exceptions.SchemaError as e:
                raise SystemExit(usage(f"{schema_path} is not a valid {cls.__name__} schema: {e.message} at {error_path(e)}"))
            validators[schema_path] = cls(schema)
        return validators[schema_path]

    files = argv[3:] if by_kind else argv[2:]
    if not by_kind:
        validator_of(argv[1])
    all_valid = True
    for path in files:
        try:
            with open(path, encoding="utf-8") as f:
                doc = json.load(f)
        except (OSError, ValueError) as e:
            print(f"{path}: cannot read JSON: {e}")
            all_valid = False
            continue
        if by_kind:
            kind = doc.get("kind") if isinstance(doc, dict) else None
            if kind not in KIND_SCHEMAS:
                print(f"{path}: INVALID (kind {kind!r} has no schema; known: {sorted(k for k in KIND_SCHEMAS if k)})")
                all_valid = False
                continue
            schema_path = f"{argv[2]}/{KIND_SCHEMAS[kind]}"
        else:
            schema_path = argv[1]
        validator = validator_of(schema_path)
        errors = sorted(validator.iter_errors(doc), key=lambda e: (error_path(e), e.message))
        for e in errors:
            print(f"{path}: {error_path(e)}: {e.message}")
        if errors:
            all_valid = False
            print(f"{path}: INVALID against {schema_path} ({len(errors)} error{'s' if len(errors) != 1 else ''})")
        else:
            print(f"{path}: valid")
    return 0 if all_valid else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
