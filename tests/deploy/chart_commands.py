"""The commands the Helm chart gives its containers, run for real on this machine (lavapipe,
loopback), as the kubelet would run them: args and env taken from `helm template`, $(VAR)
expanded from the env, Secrets written where the pod mounts them, the volume a temp folder.

1. Replicas: two `vastray serve` with the Deployment's args against a real PostgreSQL 15 (its
   own throw-away cluster, as tests/server/PostgresCluster.h starts it) share the volume. Each
   answers the gRPC health checks the probes make (grpc.health.v1 for "" and for
   vastray.v1.RenderService, through grpcurl, without the token), /readyz, and /metrics only
   with the token from the chart's Secret; /metrics has every metric the HPA's default Pods
   and External metrics name. A 2x2-tile job submitted while they are paused leaves 4 waiting
   tiles, and vastray_tasks_waiting (the HPA's default External metric) on each replica says 4.
   SIGTERM stops each within the pod's terminationGracePeriodSeconds, exit status 0.
2. Batch: the Indexed Job's script for every JOB_COMPLETION_INDEX and the assemble Job's
   script (started first: it waits for the tiles) produce the frame, and it equals
   `vastray render` of the whole frame with the same flags in every channel, bit for bit
   (OpenImageIO's idiff with no tolerance). With gpu.count 1 the tile's env hides lavapipe, and on this
   machine (no GPU) the tile fails instead of rendering on the CPU, leaving no tile file.

Usage: chart_commands.py TOOLS_DIR VASTRAY WORK_DIR. Exit 0 when all pass.
"""
import json
import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

import yaml

from chart_support import CHART, Tools, documents, find, template

HERE = pathlib.Path(__file__).resolve().parent
ENTRYPOINT = HERE.parent.parent / "deploy" / "docker" / "entrypoint.sh"
PG_BIN = pathlib.Path("/usr/lib/postgresql/15/bin")
GRPCURL = os.environ.get("GRPCURL") or shutil.which("grpcurl") or "/usr/local/bin/grpcurl"
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)
    return condition


def metric_value(metrics, name):
    """The value of the unlabelled sample `name` in a Prometheus text exposition, or None."""
    match = re.search(f"^{name} (\\S+)$", metrics, re.M)
    return match.group(1) if match else None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Postgres:
    """A throw-away PostgreSQL 15 cluster on a unix socket, run as `nobody` when we are root."""

    def __init__(self):
        self.remove_stale()
        self.dir = pathlib.Path(tempfile.mkdtemp(prefix="vastray-deploy-pg-"))
        (self.dir / "owner-pid").write_text(str(os.getpid()))
        self.running = False

    def remove_stale(self):
        """Clusters left by a run that was killed (its owner-pid is gone), not a running one's."""
        for folder in pathlib.Path(tempfile.gettempdir()).glob("vastray-deploy-pg-*"):
            try:
                os.kill(int((folder / "owner-pid").read_text()), 0)
                continue
            except (OSError, ValueError):
                pass
            if (folder / "data" / "postmaster.pid").exists():
                self.owner([str(PG_BIN / "pg_ctl"), "-D", str(folder / "data"), "-m", "immediate", "-w", "stop"])
            shutil.rmtree(folder, ignore_errors=True)

    def owner(self, command, **kwargs):
        prefix = ["runuser", "-u", "nobody", "--"] if os.geteuid() == 0 else []
        return subprocess.run(prefix + command, capture_output=True, text=True, timeout=60, **kwargs)

    def start(self):
        if os.geteuid() == 0:
            shutil.chown(self.dir, "nobody")
        data = str(self.dir / "data")
        done = self.owner([str(PG_BIN / "initdb"), "-D", data, "-U", "vastray", "-A", "trust", "-E", "UTF8",
                           "--no-sync"])
        if done.returncode:
            raise SystemExit("initdb: " + done.stdout + done.stderr)
        options = f"-c listen_addresses='' -k {self.dir} -c fsync=off"
        done = self.owner([str(PG_BIN / "pg_ctl"), "-D", data, "-o", options, "-l", str(self.dir / "log"), "-w",
                           "-t", "30", "start"])
        if done.returncode:
            raise SystemExit("pg_ctl start: " + done.stdout + done.stderr)
        self.running = True
        self.psql("postgres", "CREATE DATABASE vastray")

    def psql(self, database, sql):
        done = self.owner([str(PG_BIN / "psql"), "-h", str(self.dir), "-U", "vastray",
                           "-d", database, "-At", "-v", "ON_ERROR_STOP=1", "-c", sql])
        if done.returncode:
            raise AssertionError(f"psql {sql!r}: {done.stdout}{done.stderr}")
        return done.stdout.strip()

    def url(self):
        return f"postgresql://vastray@/vastray?host={self.dir}"

    def stop(self):
        if self.running:
            self.owner([str(PG_BIN / "pg_ctl"), "-D", str(self.dir / "data"), "-m", "immediate", "-w", "stop"])
        shutil.rmtree(self.dir, ignore_errors=True)


class Pod:
    """One container of a rendered workload, run as a local process the way the kubelet would."""

    def __init__(self, docs, workload, work, bin_dir):
        self.container = workload["spec"]["template"]["spec"]["containers"][0]
        self.spec = workload["spec"]["template"]["spec"]
        secrets = {d["metadata"]["name"]: d["stringData"] for d in docs if d["kind"] == "Secret"}
        self.env = dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}")
        for e in self.container.get("env", []):
            if "value" in e:
                self.env[e["name"]] = e["value"]
            else:
                ref = e["valueFrom"]["secretKeyRef"]
                self.env[e["name"]] = secrets[ref["name"]][ref["key"]]
        # Secret volumes: their keys as files in a folder standing for the mount path.
        self.mounts = {}
        for volume in self.spec["volumes"]:
            if "secret" in volume:
                folder = work / f"secret-{volume['name']}"
                folder.mkdir(parents=True, exist_ok=True)
                for key, value in secrets[volume["secret"]["secretName"]].items():
                    (folder / key).write_text(value)
                mount = next(m for m in self.container["volumeMounts"] if m["name"] == volume["name"])
                self.mounts[mount["mountPath"]] = str(folder)

    def expand(self, arg):
        # The kubelet's $(VAR) expansion of command and args from the container's env.
        arg = re.sub(r"\$\(([A-Za-z_][A-Za-z0-9_]*)\)", lambda m: self.env.get(m.group(1), m.group(0)), arg)
        for path, folder in self.mounts.items():
            arg = arg.replace(path + "/", folder + "/")
        return arg

    def command(self):
        # No command: the image's ENTRYPOINT runs, with args as its arguments.
        command = self.container.get("command") or image_entrypoint()
        return [self.expand(a) for a in command + self.container.get("args", [])]


def image_entrypoint():
    """deploy/Dockerfile's ENTRYPOINT, its /usr/local/bin/ standing for our bin folder on PATH."""
    line = next(l for l in (HERE.parent.parent / "deploy" / "Dockerfile").read_text().splitlines()
                if l.startswith("ENTRYPOINT "))
    return [a.removeprefix("/usr/local/bin/") for a in json.loads(line[len("ENTRYPOINT "):])]


def request(url, token=None, data=None, method=None):
    req = urllib.request.Request(url, data=data, method=method)
    if token:
        req.add_header("Authorization", f"Bearer {token}")
    try:
        with urllib.request.urlopen(req, timeout=10) as answer:
            return answer.status, answer.read().decode(errors="replace")
    except urllib.error.HTTPError as error:
        return error.code, error.read().decode(errors="replace")
    except OSError as error:
        return 0, str(error)


def grpc_health(port, service):
    body = json.dumps({"service": service})
    done = subprocess.run([GRPCURL, "-plaintext", "-max-time", "5", "-d", body, f"127.0.0.1:{port}",
                           "grpc.health.v1.Health/Check"], capture_output=True, text=True, timeout=20)
    return done.returncode == 0 and '"SERVING"' in done.stdout


def wait_for(condition, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.2)
    return False


def start_replica(pod, work, index):
    grpc, http = free_port(), free_port()
    # Each pod has its own address; here they share loopback, so each gets its own ports.
    args = [a.replace("0.0.0.0:50051", f"127.0.0.1:{grpc}").replace("0.0.0.0:8080", f"127.0.0.1:{http}")
            for a in pod.command()]
    log = open(work / f"replica-{index}.log", "w")
    process = subprocess.Popen(args, env=pod.env, stdout=log, stderr=subprocess.STDOUT)
    return process, grpc, http


def replicas(tools, vastray, work, bin_dir, scene):
    pg = Postgres()
    processes = []
    try:
        pg.start()
        code, text = template(tools, "--set", "gpu.count=0", "--set", "server.replicas=2",
                              "--set", f"database.url={pg.url()}", "--set", "auth.token=chart-token",
                              "--set", f"storage.mountPath={work}/volume", "--set", "server.memoryBudget=256MiB",
                              "--set", "server.hostCache=64MiB", "--set", "server.extraArgs={--paused}")
        if not check(code == 0, "replicas: helm template"):
            print(text)
            return
        docs = documents(text)
        deployment = find(docs, "Deployment")
        pod = Pod(docs, deployment, work, bin_dir)
        grace = deployment["spec"]["template"]["spec"]["terminationGracePeriodSeconds"]
        for i in range(2):
            processes.append(start_replica(pod, work, i))
        probes = deployment["spec"]["template"]["spec"]["containers"][0]
        live = probes["livenessProbe"]["grpc"].get("service", "")
        ready = probes["readinessProbe"]["grpc"].get("service", "")
        for i, (process, grpc, http) in enumerate(processes):
            serving = wait_for(lambda: process.poll() is not None or grpc_health(grpc, live), 60)
            if not check(serving and process.poll() is None,
                         f"replica {i}: the liveness probe's check (grpc.health.v1, service {live!r}) answers SERVING"):
                print((work / f"replica-{i}.log").read_text()[-2000:])
                continue
            check(grpc_health(grpc, ready),
                  f"replica {i}: the readiness probe's check (grpc.health.v1, service {ready!r}) answers SERVING")
            check(request(f"http://127.0.0.1:{http}/readyz")[0] == 200, f"replica {i}: /readyz 200")
            status, _ = request(f"http://127.0.0.1:{http}/metrics")
            check(status == 401, f"replica {i}: /metrics refused without the token ({status})")
            status, metrics = request(f"http://127.0.0.1:{http}/metrics", token="chart-token")
            defaults = yaml.safe_load((CHART / "values.yaml").read_text())["autoscaling"]
            names = [m["name"] for m in defaults["podsMetrics"] + defaults["externalMetrics"]]
            check(status == 200 and all(metric_value(metrics, n) is not None for n in names),
                  f"replica {i}: /metrics with the Secret's token has the HPA's metrics {names}")
        http = processes[0][2]
        status, body = request(f"http://127.0.0.1:{http}/v1/scenes?name=sphere.ply", token="chart-token",
                               data=scene.read_bytes(), method="PUT")
        if check(status in (200, 201), f"replicas: scene uploaded ({status})"):
            job = {"scene_id": json.loads(body)["id"], "width": 64, "height": 48, "spp": 1, "tiles": [2, 2]}
            status, body = request(f"http://127.0.0.1:{http}/v1/jobs", token="chart-token",
                                   data=json.dumps(job).encode(), method="POST")
            check(status == 202, f"replicas: 2x2-tile job submitted ({status})")
            for i, (_, _, port) in enumerate(processes):
                # Refreshed at most once a second: wait for the job's tiles to show.
                seen = []
                wait_for(lambda: seen.append(metric_value(request(f"http://127.0.0.1:{port}/metrics",
                                                                  token="chart-token")[1],
                                                          "vastray_tasks_waiting")) or seen[-1] == "4", 10)
                check(seen[-1:] == ["4"], f"replica {i}: vastray_tasks_waiting counts the 4 waiting tiles ({seen[-1:]})")
        for i, (process, _, _) in enumerate(processes):
            process.send_signal(signal.SIGTERM)
            try:
                code = process.wait(timeout=grace)
            except subprocess.TimeoutExpired:
                code = None
            check(code == 0, f"replica {i}: SIGTERM stops it within {grace} s, exit 0 ({code})")
    finally:
        for process, _, _ in processes:
            if process.poll() is None:
                process.kill()
                process.wait()
        pg.stop()


def batch_values(work, gpus):
    return ["--set", "server.enabled=false", "--set", "batch.enabled=true", "--set", "batch.name=frame",
            "--set", "batch.scene=scenes/sphere.ply", "--set", "batch.tiles={2,2}",
            "--set", "batch.renderArgs={--resolution=64x48,--spp=2,--aovs=depth\\,normal}",
            "--set", f"gpu.count={gpus}", "--set", f"storage.mountPath={work}/volume"]


def batch(tools, vastray, work, bin_dir):
    code, text = template(tools, *batch_values(work, 0))
    if not check(code == 0, "batch: helm template"):
        print(text)
        return
    docs = documents(text)
    tiles, assemble = find(docs, "Job", "-tiles"), find(docs, "Job", "-assemble")
    out = pathlib.Path(Pod(docs, assemble, work, bin_dir).env["VASTRAY_OUT"])
    assembler = Pod(docs, assemble, work, bin_dir)
    assembler.env["VASTRAY_POLL_SECONDS"] = "0.2"
    waiting = subprocess.Popen(assembler.command(), env=assembler.env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    try:
        for i in range(tiles["spec"]["completions"]):
            pod = Pod(docs, tiles, work, bin_dir)
            pod.env["JOB_COMPLETION_INDEX"] = str(i)
            done = subprocess.run(pod.command(), env=pod.env, capture_output=True, text=True, timeout=60)
            check(done.returncode == 0 and (out / f"tile-{i}.exr").is_file(),
                  f"batch: pod {i} of the Indexed Job wrote tile-{i}.exr" + ("" if done.returncode == 0
                                                                             else "\n" + done.stdout + done.stderr))
        try:
            log, _ = waiting.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            waiting.kill()
            log, _ = waiting.communicate()
        frame = out / "frame.exr"
        check(waiting.returncode == 0 and frame.is_file(), "batch: the assemble Job waited for 4 tiles and wrote "
              "frame.exr" + ("" if waiting.returncode == 0 else "\n" + log))
        check(not list(out.glob(".*")), "batch: no temporary file left on the volume")
        whole = work / "whole.exr"
        flags = tiles["spec"]["template"]["spec"]["containers"][0]["args"]
        scene = work / "volume" / "scenes" / "sphere.ply"
        subprocess.run([vastray, "render", scene, "-o", whole, *flags], check=True, capture_output=True, timeout=60)
        # OpenImageIO's idiff (install-deps.sh: openimageio-tools) over every channel, no tolerance:
        # the files' bytes differ (EXR header attributes), the pixels must not.
        done = subprocess.run(["idiff", "-fail", "0", "-failpercent", "0", "-warn", "0", frame, whole],
                              capture_output=True, text=True, timeout=60)
        check(done.returncode == 0, "batch: the assembled frame equals the whole-frame render, every channel "
              f"bit for bit (idiff: {done.stdout.strip().splitlines()[-1]})")
    finally:
        if waiting.poll() is None:
            waiting.kill()
            waiting.wait()

    # With a GPU asked for, the tile must not fall back to lavapipe.
    code, text = template(tools, *batch_values(work / "gpu", 1))
    docs = documents(text)
    pod = Pod(docs, find(docs, "Job", "-tiles"), work, bin_dir)
    pod.env["JOB_COMPLETION_INDEX"] = "0"
    (work / "gpu" / "volume" / "scenes").mkdir(parents=True, exist_ok=True)
    shutil.copy(scene, work / "gpu" / "volume" / "scenes")
    done = subprocess.run(pod.command(), env=pod.env, capture_output=True, text=True, timeout=60)
    said = (done.stderr + done.stdout).strip()
    check(done.returncode != 0 and "Vulkan" in said
          and not (work / "gpu" / "volume" / "batch" / "frame" / "tile-0.exr").exists(),
          f"batch: with gpu.count 1 and no GPU the tile fails (lavapipe hidden), no tile written: {said[-200:]}")


def main():
    tools = Tools(sys.argv[1])
    vastray, work = pathlib.Path(sys.argv[2]).resolve(), pathlib.Path(sys.argv[3]).resolve()
    shutil.rmtree(work, ignore_errors=True)
    bin_dir = work / "bin"
    bin_dir.mkdir(parents=True)
    # The image's /usr/local/bin: its entry point script and the binary.
    shutil.copy(ENTRYPOINT, bin_dir / "vastray-entrypoint")
    (bin_dir / "vastray").symlink_to(vastray)
    scenes = work / "volume" / "scenes"
    scenes.mkdir(parents=True)
    scene = scenes / "sphere.ply"
    subprocess.run([vastray, "generate", "sphere", "--triangles", "2000", "-o", scene], check=True,
                   capture_output=True, timeout=60)
    if os.geteuid() == 0:  # PostgreSQL runs as nobody; the replicas as us
        os.chmod(work, 0o755)
    replicas(tools, vastray, work, bin_dir, scene)
    batch(tools, vastray, work, bin_dir)
    print(f"{len(failures)} failed" if failures else "all chart command checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
