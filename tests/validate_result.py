#!/usr/bin/python3
"""Validate suite result files against a JSON Schema.

Usage: validate_result.py SCHEMA|SCHEMA_DIR FILE...
       validate_result.py --by-kind SCHEMA_DIR FILE...

With a directory (results/schema), each file must be a run's result file (no top-level "kind"),
validated against DIR/vN.json for its own schema_version N, so that files of every version the
suite reads (1 and 2) are checked by the schema that describes them. With --by-kind, each file
against the schema of its own kind: a run's result as above, a roofline file against the schema
KIND_SCHEMAS names; a file of a kind with no schema is invalid, so that a new kind of file cannot
go unchecked. With a schema file, every file against that one schema.

Prints one line per violation, "FILE: $.json.path: message", and a summary line per file.
Exit status: 0 all files valid, 1 at least one file invalid or unreadable, 2 usage error
(wrong arguments, or a schema that cannot be read or is not itself a valid schema).

Needs the jsonschema package (Debian: python3-jsonschema, 4.x); run it with /usr/bin/python3.
The validator class follows the schema's "$schema" (draft 2020-12 for results/schema/v2.json).
"""

import json
import os
import sys


def usage(message):
    print(f"validate_result.py: {message}", file=sys.stderr)
    print("usage: validate_result.py SCHEMA|SCHEMA_DIR FILE... | --by-kind SCHEMA_DIR FILE...", file=sys.stderr)
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


# Each kind of file the suite writes other than a run's result, by its top-level "kind", and the
# schema in results/schema/ that describes it.
KIND_SCHEMAS = {
    "suite-roofline": "roofline-v1.json",
    "suite-roofline-placement": "roofline-v1.json",
}


class SchemaError(Exception):
    pass


def load_validator(jsonschema, validator_for, schema_path):
    """The validator of one schema file; SchemaError when it cannot be read or is not a schema."""
    try:
        with open(schema_path, encoding="utf-8") as f:
            schema = json.load(f)
    except (OSError, ValueError) as e:
        raise SchemaError(f"cannot read schema {schema_path}: {e}")
    cls = validator_for(schema, default=jsonschema.Draft202012Validator)
    try:
        cls.check_schema(schema)
    except jsonschema.exceptions.SchemaError as e:
        raise SchemaError(f"{schema_path} is not a valid {cls.__name__} schema: {e.message} at {error_path(e)}")
    return cls(schema)


def main(argv):
    by_kind = len(argv) > 1 and argv[1] == "--by-kind"
    if by_kind:
        if len(argv) < 4 or not os.path.isdir(argv[2]):
            return usage("--by-kind needs a schema directory and at least one file")
        argv = argv[:1] + argv[2:]
    if len(argv) < 3 or argv[1] in ("-h", "--help"):
        return usage("need a schema and at least one file")
    try:
        import jsonschema
        from jsonschema.validators import validator_for
    except ImportError:
        return usage(f"the jsonschema module is missing for {sys.executable} (install python3-jsonschema)")

    schema_path = argv[1]
    by_version = os.path.isdir(schema_path)
    validators = {}
    try:
        if not by_version:
            validators[None] = load_validator(jsonschema, validator_for, schema_path)
    except SchemaError as e:
        return usage(str(e))

    all_valid = True
    for path in argv[2:]:
        try:
            with open(path, encoding="utf-8") as f:
                doc = json.load(f)
        except (OSError, ValueError) as e:
            print(f"{path}: cannot read JSON: {e}")
            all_valid = False
            continue
        key = None
        if by_version:
            kind = doc.get("kind") if isinstance(doc, dict) else None
            if kind is not None and not by_kind:
                print(f"{path}: INVALID (a {kind!r} file, not a run's result file)")
                all_valid = False
                continue
            if kind is not None:
                if kind not in KIND_SCHEMAS:
                    print(f"{path}: INVALID (kind {kind!r} has no schema; known: {sorted(KIND_SCHEMAS)})")
                    all_valid = False
                    continue
                key, schema_file = kind, os.path.join(schema_path, KIND_SCHEMAS[kind])
            else:
                key = doc.get("schema_version") if isinstance(doc, dict) else None
                schema_file = os.path.join(schema_path, f"v{key}.json")
                if not isinstance(key, int) or isinstance(key, bool) or not os.path.isfile(schema_file):
                    print(f"{path}: $.schema_version: {key!r} has no schema in {schema_path}")
                    all_valid = False
                    continue
            if key not in validators:
                try:
                    validators[key] = load_validator(jsonschema, validator_for, schema_file)
                except SchemaError as e:
                    return usage(str(e))
        errors = sorted(validators[key].iter_errors(doc), key=lambda e: (error_path(e), e.message))
        for e in errors:
            print(f"{path}: {error_path(e)}: {e.message}")
        if errors:
            all_valid = False
            print(f"{path}: INVALID ({len(errors)} error{'s' if len(errors) != 1 else ''})")
        else:
            print(f"{path}: valid")
    return 0 if all_valid else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
