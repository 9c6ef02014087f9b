"""Converts a YAML document (an API description) to JSON, so the server can serve and check against it."""
import json
import sys

import yaml

with open(sys.argv[1], encoding="utf-8") as source:
    document = yaml.safe_load(source)
with open(sys.argv[2], "w", encoding="utf-8") as target:
    json.dump(document, target, indent=1, ensure_ascii=False)
    target.write("\n")
