"""Checks JSON files against the campaign JSON Schema; prints 'valid' or the first error per file."""
import json
import sys

import jsonschema

schema = json.load(open(sys.argv[1]))
validator = jsonschema.Draft202012Validator(schema)
for path in sys.argv[2:]:
    errors = sorted(validator.iter_errors(json.load(open(path))), key=lambda e: list(e.path))
    print(path, "valid" if not errors else "invalid: " + errors[0].message)
