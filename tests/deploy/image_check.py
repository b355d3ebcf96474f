"""The chart's commands run in the image built from deploy/Dockerfile, with Docker, as the
kubelet would run them (args and env from `helm template`, Secrets and the volume bind-mounted
where the pod mounts them, uid 10001, no network but loopback):

1. The server Deployment (one SQLite server, lavapipe, a token): the readiness and liveness
   probes' gRPC health checks answer SERVING (grpcurl), /metrics answers with the token, and
   `docker stop` (SIGTERM) ends it with status 0 within terminationGracePeriodSeconds.
2. The batch Jobs: the tile script for every JOB_COMPLETION_INDEX and the assemble script give
   a frame equal in every channel (idiff, no tolerance) to `vastray render` of the whole frame
   in the same image. With gpu.count 1 (lavapipe hidden) and no GPU, a tile fails.

Not part of `make test` (CI has no container daemon). Usage:
  image_check.py TOOLS_DIR IMAGE WORK_DIR      e.g. /opt/vastray/deploy-tools vastray:0.1.0 /tmp/ic
with DOCKER_HOST pointing at a daemon. Exit 0 when all pass.
"""
import os
import pathlib
import shutil
import subprocess
import sys
import time

from chart_commands import check, failures, free_port, grpc_health, request, wait_for
from chart_support import Tools, documents, find, template

UID = "10001:10001"


def docker(*args, timeout=120):
    return subprocess.run(["docker", *map(str, args)], capture_output=True, text=True, timeout=timeout)


def secret_mounts(docs, workload, work):
    """-v options for the pod's Secret volumes, their keys written to host folders."""
    secrets = {d["metadata"]["name"]: d["stringData"] for d in docs if d["kind"] == "Secret"}
    spec = workload["spec"]["template"]["spec"]
    options = []
    for volume in spec["volumes"]:
        if "secret" not in volume:
            continue
        folder = work / f"secret-{volume['name']}"
        folder.mkdir(parents=True, exist_ok=True)
        for key, value in secrets[volume["secret"]["secretName"]].items():
            (folder / key).write_text(value)
            os.chmod(folder / key, 0o644)
        mount = next(m for m in spec["containers"][0]["volumeMounts"] if m["name"] == volume["name"])
        options += ["-v", f"{folder}:{mount['mountPath']}:ro"]
    return options


def env_options(container, extra=None):
    options = []
    for e in container.get("env", []):
        if "value" in e:
            options += ["-e", f"{e['name']}={e['value']}"]
    for name, value in (extra or {}).items():
        options += ["-e", f"{name}={value}"]
    return options


def run_pod(image, volume, container, extra_env=None, mounts=(), name=None, detach=False):
    """docker run of one container spec: its command replaces the entry point, as in a pod."""
    # A detached server is kept after it exits, for its exit status; the finally of server() removes it.
    options = ([] if detach else ["--rm"]) + ["--user", UID, "-v", f"{volume}:/data", *mounts,
                                              *env_options(container, extra_env)]
    if name:
        options += ["--name", name]
    command = container.get("command", [])
    if command:
        options += ["--entrypoint", command[0]]
    args = command[1:] + container.get("args", [])
    if detach:
        return docker("run", "-d", "--network", "host", *options, image, *args)
    return docker("run", "--network", "none", *options, image, *args, timeout=300)


def server(tools, image, work, volume):
    grpc, http = free_port(), free_port()
    code, text = template(tools, "--set", "gpu.count=0", "--set", "auth.token=image-token",
                          "--set", f"server.grpcPort={grpc}", "--set", f"server.httpPort={http}",
                          "--set", "server.memoryBudget=256MiB", "--set", "server.hostCache=64MiB")
    if not check(code == 0, "image server: helm template"):
        print(text)
        return
    docs = documents(text)
    deployment = find(docs, "Deployment")
    container = dict(deployment["spec"]["template"]["spec"]["containers"][0])
    # Loopback only: the pod's 0.0.0.0 becomes 127.0.0.1 on the host's network.
    container["args"] = [a.replace("0.0.0.0:", "127.0.0.1:") for a in container["args"]]
    name = f"vastray-image-check-{os.getpid()}"
    started = run_pod(image, volume, container, mounts=secret_mounts(docs, deployment, work), name=name,
                      detach=True)
    if not check(started.returncode == 0, "image server: docker run"):
        print(started.stderr)
        return
    try:
        live = container["livenessProbe"]["grpc"].get("service", "")
        ready = container["readinessProbe"]["grpc"].get("service", "")
        check(wait_for(lambda: grpc_health(grpc, live), 60), f"image server: liveness check {live!r} SERVING")
        check(grpc_health(grpc, ready), f"image server: readiness check {ready!r} SERVING")
        status, metrics = request(f"http://127.0.0.1:{http}/metrics", token="image-token")
        check(status == 200 and "vastray_jobs_running " in metrics, f"image server: /metrics with the token ({status})")
        grace = deployment["spec"]["template"]["spec"]["terminationGracePeriodSeconds"]
        begin = time.monotonic()
        docker("stop", "-t", grace, name, timeout=grace + 30)
        code = docker("inspect", "-f", "{{.State.ExitCode}}", name).stdout.strip()
        check(time.monotonic() - begin < grace and code == "0",
              f"image server: SIGTERM stops it within {grace} s (status {code})")
    finally:
        docker("rm", "-f", name)


def batch(tools, image, work, volume):
    args = ["--set", "server.enabled=false", "--set", "batch.enabled=true", "--set", "batch.name=frame",
            "--set", "batch.scene=scenes/sphere.ply", "--set", "batch.tiles={2,2}",
            "--set", "batch.renderArgs={--resolution=64x48,--spp=2,--aovs=depth\\,normal}", "--set", "gpu.count=0"]
    code, text = template(tools, *args)
    docs = documents(text)
    tiles, assemble = find(docs, "Job", "-tiles"), find(docs, "Job", "-assemble")
    tile = tiles["spec"]["template"]["spec"]["containers"][0]
    for i in range(tiles["spec"]["completions"]):
        done = run_pod(image, volume, tile, {"JOB_COMPLETION_INDEX": i})
        check(done.returncode == 0, f"image batch: tile pod {i}" + ("" if done.returncode == 0 else "\n" + done.stderr))
    done = run_pod(image, volume, assemble["spec"]["template"]["spec"]["containers"][0])
    check(done.returncode == 0 and "assemble: wrote /data/batch/frame/frame.exr" in done.stdout,
          "image batch: assemble pod wrote frame.exr" + ("" if done.returncode == 0 else "\n" + done.stderr))
    whole = docker("run", "--rm", "--network", "none", "--user", UID, "-v", f"{volume}:/data", image, "render",
                   "scenes/sphere.ply", "-o", "whole.exr", *tile["args"], timeout=300)
    check(whole.returncode == 0, "image batch: whole-frame render in the image")
    same = subprocess.run(["idiff", "-fail", "0", "-failpercent", "0", "-warn", "0",
                           volume / "batch" / "frame" / "frame.exr", volume / "whole.exr"], capture_output=True,
                          text=True)
    check(same.returncode == 0, "image batch: frame equals the whole-frame render in every channel (idiff: "
          + same.stdout.strip().splitlines()[-1] + ")")
    code, text = template(tools, *args[:-2], "--set", "gpu.count=1")
    docs = documents(text)
    tile = find(docs, "Job", "-tiles")["spec"]["template"]["spec"]["containers"][0]
    done = run_pod(image, volume, tile, {"JOB_COMPLETION_INDEX": 0, "VASTRAY_OUT": "/data/gpu"})
    check(done.returncode != 0 and "Vulkan" in done.stderr and not (volume / "gpu" / "tile-0.exr").exists(),
          "image batch: with gpu.count 1 and no GPU the tile fails: " + done.stderr.strip()[-120:])


def main():
    tools, image, work = Tools(sys.argv[1]), sys.argv[2], pathlib.Path(sys.argv[3]).resolve()
    shutil.rmtree(work, ignore_errors=True)
    volume = work / "volume"
    (volume / "scenes").mkdir(parents=True)
    os.chown(volume, 10001, 10001)  # the pods run as uid 10001
    os.chown(volume / "scenes", 10001, 10001)
    made = docker("run", "--rm", "--network", "none", "--user", UID, "-v", f"{volume}:/data", image, "generate",
                  "sphere", "--triangles", "2000", "-o", "scenes/sphere.ply")
    if made.returncode != 0:
        raise SystemExit("vastray generate in the image: " + made.stderr)
    server(tools, image, work, volume)
    batch(tools, image, work, volume)
    print(f"{len(failures)} failed" if failures else "all image checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
