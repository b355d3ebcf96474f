"""The Helm chart (deploy/helm/vastray) checked with real tools, offline:

- `helm lint` with the chart's defaults and each file in tests/deploy/values/;
- `helm template` of each, validated against the Kubernetes JSON schemas of the oldest
  supported (1.29) and the newest bundled (1.37) Kubernetes by `kubeconform -strict` and by
  `kubernetes-validate --strict` (scripts/install-deploy-tools.sh installs both);
- the properties the chart promises: GPU limits, gRPC probes, the headless Service, the HPA's
  target, the Indexed Job's completions, Secrets mounted, nothing left unset;
- that the validators and the chart do fail: manifests broken on purpose (a wrong type, a
  misspelt field, a missing required field) must be rejected by both validators, and values the
  chart refuses (an unknown key, replicas without PostgreSQL) must fail `helm template`.

Usage: validate_chart.py TOOLS_DIR (default /opt/vastray/deploy-tools). Exit 0 when all pass.
"""
import copy
import sys
import tempfile

import yaml

from chart_support import CHART, VALUES, Tools, documents, find, run, template

KUBE_VERSIONS = ["1.29.0", "1.37.0"]
SCENARIOS = {"defaults": [], **{p.stem: ["-f", str(p)] for p in sorted(VALUES.glob("*.yaml"))}}
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        failures.append(what)


def kubeconform(tools, text, version):
    location = str(tools.schemas) + "/{{ .NormalizedKubernetesVersion }}-local-strict/" \
        "{{ .ResourceKind }}{{ .KindSuffix }}.json"
    return run([tools.kubeconform, "-strict", "-summary", "-schema-location", location,
                "-kubernetes-version", version, "-"], stdin=text)


def kubernetes_validate(tools, text, version):
    with tempfile.NamedTemporaryFile("w", suffix=".yaml") as f:
        f.write(text)
        f.flush()
        return run([tools.kubernetes_validate, "--strict", "--quiet", "-k", version, f.name])


def validate_scenarios(tools):
    rendered = {}
    for name, args in SCENARIOS.items():
        code, out = run([tools.helm, "lint", CHART, "--strict", "--kube-version", KUBE_VERSIONS[0], *args])
        check(code == 0, f"helm lint --strict ({name})" + ("" if code == 0 else "\n" + out))
        for version in KUBE_VERSIONS:
            code, text = template(tools, *args, kube_version=version)
            check(code == 0, f"helm template ({name}, Kubernetes {version})" + ("" if code == 0 else "\n" + text))
            if code != 0:
                continue
            rendered[name] = text
            code, out = kubeconform(tools, text, version)
            check(code == 0 and "Invalid: 0, Errors: 0" in out,
                  f"kubeconform -strict ({name}, {version}): {out.strip().splitlines()[-1]}"
                  + ("" if code == 0 else "\n" + out))
            code, out = kubernetes_validate(tools, text, version)
            check(code == 0, f"kubernetes-validate --strict ({name}, {version})" + ("" if code == 0 else "\n" + out))
    return rendered


def container(workload):
    return workload["spec"]["template"]["spec"]["containers"][0]


def check_defaults(docs):
    deployment = find(docs, "Deployment")
    c = container(deployment)
    check(deployment["spec"]["replicas"] == 1 and deployment["spec"]["strategy"]["type"] == "Recreate",
          "defaults: one SQLite server, replaced with Recreate")
    check("--data-dir=/data/service" in c["args"] and not any(a.startswith("--database") for a in c["args"]),
          "defaults: --data-dir on the volume, no --database")
    check(c["resources"]["limits"].get("nvidia.com/gpu") == 1, "defaults: nvidia.com/gpu limit 1")
    check({"name": "VK_LOADER_DRIVERS_DISABLE", "value": "lvp_icd*"} in c["env"],
          "defaults: lavapipe hidden from the Vulkan loader when a GPU is asked for")
    check(c["livenessProbe"]["grpc"] == {"port": 50051}, "defaults: gRPC liveness probe on the gRPC port")
    check(c["readinessProbe"]["grpc"] == {"port": 50051, "service": "vastray.v1.RenderService"},
          "defaults: gRPC readiness probe asks about vastray.v1.RenderService")
    check("--grpc=0.0.0.0:50051" in c["args"] and "--http=0.0.0.0:8080" in c["args"],
          "defaults: listens on all addresses (vastray serve's default is loopback)")
    headless = find(docs, "Service", "-grpc")
    check(headless["spec"]["clusterIP"] == "None", "defaults: headless gRPC Service")
    check(find(docs, "Service", "-vastray")["spec"]["type"] == "ClusterIP", "defaults: ClusterIP Service")
    check(find(docs, "PersistentVolumeClaim")["spec"]["accessModes"] == ["ReadWriteMany"],
          "defaults: ReadWriteMany PVC")
    check(find(docs, "PodDisruptionBudget")["spec"]["maxUnavailable"] == 1, "defaults: PodDisruptionBudget")
    check(not [d for d in docs if d["kind"] in ("HorizontalPodAutoscaler", "Job", "Secret")],
          "defaults: no HPA, Job or Secret")


def check_lavapipe(docs):
    c = container(find(docs, "Deployment"))
    check("nvidia.com/gpu" not in c["resources"].get("limits", {}), "lavapipe: no GPU limit")
    check("VK_LOADER_DRIVERS_DISABLE" not in str(c.get("env", [])), "lavapipe: lavapipe left visible")
    check("--gpu-device=0,0" in c["args"], "lavapipe: --gpu-device from server.gpuDevices")
    secret = find(docs, "Secret", "-token")
    check(secret["stringData"] == {"token": "test-token"}, "lavapipe: the token as a Secret")
    check("--auth-token-file=/etc/vastray/token/token" in c["args"]
          and {"name": "token", "mountPath": "/etc/vastray/token", "readOnly": True} in c["volumeMounts"],
          "lavapipe: the token Secret mounted for --auth-token-file")


def check_replicas(docs):
    deployment = find(docs, "Deployment")
    spec = deployment["spec"]["template"]["spec"]
    c = container(deployment)
    check("replicas" not in deployment["spec"], "replicas: the HPA owns the replica count")
    check("strategy" not in deployment["spec"], "replicas: rolling update")
    check("--storage=/data/service" in c["args"] and "--database=$(VASTRAY_DATABASE_URL)" in c["args"],
          "replicas: --storage and --database from the env")
    env = {e["name"]: e for e in c["env"]}
    check(env["VASTRAY_DATABASE_URL"]["valueFrom"]["secretKeyRef"] == {"name": "vastray-database", "key": "url"},
          "replicas: database URL from the existing Secret")
    check(env["PGPASSWORD"]["valueFrom"]["secretKeyRef"] == {"name": "vastray-database", "key": "password"},
          "replicas: PGPASSWORD from a Secret")
    check("--gpu-device=0,1" in c["args"] and c["resources"]["limits"]["nvidia.com/gpu"] == 2,
          "replicas: two GPUs, one worker each")
    check(spec["runtimeClassName"] == "nvidia", "replicas: runtimeClassName")
    check(spec["volumes"][0]["persistentVolumeClaim"]["claimName"] == "render-share"
          and not [d for d in docs if d["kind"] == "PersistentVolumeClaim"], "replicas: the existing claim")
    check(c["args"][-1] == "--paused", "replicas: extraArgs appended")
    hpa = find(docs, "HorizontalPodAutoscaler")
    target = {"apiVersion": "apps/v1", "kind": "Deployment", "name": deployment["metadata"]["name"]}
    check(hpa["spec"]["scaleTargetRef"] == target, "replicas: HPA targets the Deployment")
    kinds = [(m["type"], m.get("pods", m.get("external"))["metric"]["name"]) for m in hpa["spec"]["metrics"]]
    check(kinds == [("Pods", "vastray_jobs_running"), ("External", "vastray_tasks_waiting")],
          "replicas: HPA on the Pods and External metrics")
    check(not [d for d in docs if d["kind"] == "Secret"], "replicas: no Secret made when existing ones are named")


def check_default_hpa(tools):
    """Autoscaling with the chart's default metrics: the waiting tiles as an External metric (a
    figure for the whole database) and the busy workers per pod."""
    code, text = template(tools, "--set", "autoscaling.enabled=true", "--set", "database.url=postgresql://v@db/v")
    if not check(code == 0, "autoscaling defaults: helm template" + ("" if code == 0 else "\n" + text)):
        return
    metrics = find(documents(text), "HorizontalPodAutoscaler")["spec"]["metrics"]
    check(metrics == [
        {"type": "Pods", "pods": {"metric": {"name": "vastray_jobs_running"},
                                  "target": {"type": "AverageValue", "averageValue": "800m"}}},
        {"type": "External", "external": {"metric": {"name": "vastray_tasks_waiting"},
                                          "target": {"type": "AverageValue", "averageValue": "2"}}}],
        f"autoscaling defaults: External vastray_tasks_waiting and Pods vastray_jobs_running ({metrics})")


def check_batch(docs):
    check(not [d for d in docs if d["kind"] in ("Deployment", "Service", "PodDisruptionBudget")],
          "batch: no server")
    tiles = find(docs, "Job", "-tiles")
    assemble = find(docs, "Job", "-assemble")
    check(tiles["spec"]["completionMode"] == "Indexed" and tiles["spec"]["completions"] == 6,
          "batch: Indexed Job of 3x2 = 6 completions")
    script = container(tiles)["command"][2]
    check("--tiles 3,2 --tile \"$i\"" in script and "i=$JOB_COMPLETION_INDEX" in script,
          "batch: pod i renders tile i of the grid")
    check(container(tiles)["args"] == ["--resolution=640x360", "--spp=16"], "batch: render flags as args")
    env = {e["name"]: e["value"] for e in container(assemble)["env"]}
    check(env["VASTRAY_TILES"] == "6" and env["VASTRAY_OUT"] == "/data/batch/shot-010",
          "batch: assemble waits for 6 tiles in the frame's folder")
    check(tiles["spec"]["template"]["spec"]["restartPolicy"] == "Never", "batch: restartPolicy Never")


def refused(tools, what, *args, expect, kube_version="1.29.0"):
    code, out = template(tools, *args, kube_version=kube_version)
    check(code != 0 and expect in out, f"refused: {what}" + ("" if code != 0 else " (helm template passed)"))


def broken_manifests(docs):
    """Copies of the defaults' Deployment, each broken in one way the schemas must catch, with
    the word each validator's message must name (so that an unrelated failure does not pass)."""
    deployment = find(docs, "Deployment")
    broken = {}
    d = copy.deepcopy(deployment)
    d["spec"]["replicas"] = "three"
    broken["replicas is a string"] = (d, "replicas")
    d = copy.deepcopy(deployment)
    container(d)["imagePullPolicyy"] = "Always"
    broken["misspelt container field (strict)"] = (d, "imagePullPolicyy")
    d = copy.deepcopy(deployment)
    del d["spec"]["selector"]
    broken["selector missing"] = (d, "selector")
    d = copy.deepcopy(deployment)
    container(d)["livenessProbe"]["grpc"]["port"] = "grpc"
    broken["gRPC probe port by name (must be a number)"] = (d, "port")
    return broken


def main():
    tools = Tools(sys.argv[1] if len(sys.argv) > 1 else "/opt/vastray/deploy-tools")
    rendered = validate_scenarios(tools)
    checks = {"defaults": check_defaults, "lavapipe": check_lavapipe, "replicas": check_replicas,
              "batch": check_batch}
    for name, test in checks.items():
        if name in rendered:
            test(documents(rendered[name]))
        else:
            check(False, f"{name}: not rendered")
    if "defaults" in rendered:
        for what, (manifest, word) in broken_manifests(documents(rendered["defaults"])).items():
            text = yaml.safe_dump(manifest)
            for version in KUBE_VERSIONS:
                code, out = kubeconform(tools, text, version)
                check(code != 0 and word in out,
                      f"kubeconform rejects {what} ({version})" + ("" if code else "\n" + out))
                code, out = kubernetes_validate(tools, text, version)
                check(code != 0 and word in out,
                      f"kubernetes-validate rejects {what} ({version})" + ("" if code else "\n" + out))
    check_default_hpa(tools)
    refused(tools, "an unknown values key", "--set", "server.replica=3", expect="additional properties 'replica'")
    refused(tools, "replicas without PostgreSQL", "--set", "server.replicas=2", expect="need database")
    refused(tools, "autoscaling without PostgreSQL", "--set", "autoscaling.enabled=true", expect="need database")
    refused(tools, "a batch without a scene", "--set", "batch.enabled=true", expect="needs batch.scene")
    refused(tools, "Kubernetes older than 1.29", kube_version="1.28.0", expect="kubeVersion")
    print(f"{len(failures)} failed" if failures else "all deploy chart checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
