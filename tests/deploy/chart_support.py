"""What the deploy tests share: the tools' paths and `helm template` of the chart."""
import pathlib
import subprocess

import yaml

HERE = pathlib.Path(__file__).resolve().parent
CHART = HERE.parent.parent / "deploy" / "helm" / "vastray"
VALUES = HERE / "values"


class Tools:
    """The binaries scripts/install-deploy-tools.sh installs under one folder."""

    def __init__(self, root):
        root = pathlib.Path(root)
        self.helm = root / "bin" / "helm"
        self.kubeconform = root / "bin" / "kubeconform"
        self.kubernetes_validate = root / "venv" / "bin" / "kubernetes-validate"
        self.schemas = root / "schemas"
        missing = [str(p) for p in (self.helm, self.kubeconform, self.kubernetes_validate, self.schemas)
                   if not p.exists()]
        if missing:
            raise SystemExit(f"missing {', '.join(missing)}: run scripts/install-deploy-tools.sh")


def run(command, stdin=None, timeout=120):
    """Runs a command; returns (exit code, stdout + stderr)."""
    done = subprocess.run([str(c) for c in command], input=stdin, capture_output=True, text=True,
                          timeout=timeout)
    return done.returncode, done.stdout + done.stderr


def template(tools, *args, kube_version="1.29.0"):
    """`helm template` of the chart; returns (exit code, YAML text or the error)."""
    code, out = run([tools.helm, "template", "t", CHART, "--kube-version", kube_version, *args])
    return code, out


def documents(text):
    return [d for d in yaml.safe_load_all(text) if d]


def find(docs, kind, name_suffix=""):
    found = [d for d in docs if d["kind"] == kind and d["metadata"]["name"].endswith(name_suffix)]
    if len(found) != 1:
        raise AssertionError(f"expected one {kind} named *{name_suffix}, found {len(found)}")
    return found[0]
