"""Writes kubernetes-validate's bundled Kubernetes JSON schemas of one version where kubeconform
can read them offline: usage local_schemas.py VERSION OUT_DIR (run with the venv's python).

The bundled files name each other by URL: each has "$id": "https://kubernetes.io/api/..." and
refers to "/api/_definitions.json#/$defs/...", which kubeconform would resolve to
https://kubernetes.io/api/_definitions.json and try to fetch. Dropping $id and making the
reference relative lets it resolve to _definitions.json beside each file. Nothing else changes.
"""
import json
import pathlib
import sys

import kubernetes_validate


def local(node):
    if isinstance(node, dict):
        # Only string values are keywords: "$ref" is also a property name (of
        # CustomResourceDefinition's JSONSchemaProps), whose value is a schema.
        return {
            key: (value.replace("/api/_definitions.json#", "_definitions.json#")
                  if isinstance(value, str) and key == "$ref" else local(value))
            for key, value in node.items()
            if not (key == "$id" and isinstance(value, str))
        }
    if isinstance(node, list):
        return [local(value) for value in node]
    return node


def main():
    version, out = sys.argv[1], pathlib.Path(sys.argv[2])
    package = pathlib.Path(kubernetes_validate.__file__).parent
    src = package / "kubernetes-json-schema" / f"v{version}-local-strict"
    if not src.is_dir():
        sys.exit(f"local_schemas: kubernetes-validate has no schemas for Kubernetes {version} ({src})")
    # Written beside and renamed at the end: an interrupted run leaves no half directory behind
    # that install-deploy-tools.sh would take as done.
    tmp = out.with_name(out.name + ".tmp")
    tmp.mkdir(parents=True, exist_ok=True)
    count = 0
    for schema in src.glob("*.json"):
        (tmp / schema.name).write_text(json.dumps(local(json.loads(schema.read_text()))))
        count += 1
    if count == 0 or not (tmp / "_definitions.json").is_file():
        sys.exit(f"local_schemas: no _definitions.json among {count} files in {src}")
    tmp.rename(out)
    print(f"local_schemas: {count} schemas of Kubernetes {version} in {out}")


if __name__ == "__main__":
    main()
