#!/usr/bin/python3
"""Validate suite result files against a JSON Schema.

Usage: validate_result.py SCHEMA FILE...

Prints one line per violation, "FILE: $.json.path: message", and a summary line per file.
Exit status: 0 all files valid, 1 at least one file invalid or unreadable, 2 usage error
(wrong arguments, or a schema that cannot be read or is not itself a valid schema).

Needs the jsonschema package (Debian: python3-jsonschema, 4.x); run it with /usr/bin/python3.
The validator class follows the schema's "$schema" (draft 2020-12 for results/schema/v1.json).
"""

import json
import sys


def usage(message):
    print(f"validate_result.py: {message}", file=sys.stderr)
    print("usage: validate_result.py SCHEMA FILE...", file=sys.stderr)
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

    schema_path = argv[1]
    try:
        with open(schema_path, encoding="utf-8") as f:
            schema = json.load(f)
    except (OSError, ValueError) as e:
        return usage(f"cannot read schema {schema_path}: {e}")

    cls = validator_for(schema, default=jsonschema.Draft202012Validator)
    try:
        cls.check_schema(schema)
    except jsonschema.exceptions.SchemaError as e:
        return usage(f"{schema_path} is not a valid {cls.__name__} schema: {e.message} at {error_path(e)}")
    validator = cls(schema)

    all_valid = True
    for path in argv[2:]:
        try:
            with open(path, encoding="utf-8") as f:
                doc = json.load(f)
        except (OSError, ValueError) as e:
            print(f"{path}: cannot read JSON: {e}")
            all_valid = False
            continue
        errors = sorted(validator.iter_errors(doc), key=lambda e: (error_path(e), e.message))
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
