#!/bin/bash
# Measurement, not a test (docs/PERFORMANCE.md, "Replicas"): job time of one 128x128 render of a
# 2000-triangle sphere as 1x1, 2x2, 4x4 and 8x8 tiles on N replicas (`serve --storage`) sharing
# a throw-away PostgreSQL cluster; median of 3 runs each, after one warm-up job.
# Usage: tests/server/replica_tiles_bench.sh BUILD_DIR [SPP=64] [REPLICAS=1]  (as root: the
# cluster runs as nobody)
set -e
B=/usr/lib/postgresql/15/bin
V=$(realpath "$1")/vastray
shift
D=$(mktemp -d /tmp/vastray-bench-XXXXXX); chown nobody $D
runuser -u nobody -- $B/initdb -D $D/data -U vastray -A trust --no-sync >/dev/null
runuser -u nobody -- $B/pg_ctl -D $D/data -o "-c listen_addresses='' -k $D -c fsync=off" -l $D/log -w start >/dev/null
URL="postgresql://vastray@/postgres?host=$D"
python3 - "$V" "$URL" "$D" "$@" <<'PY'
import json, subprocess, sys, time, urllib.request, re, os
v, url, d = sys.argv[1:4]
spp = int(sys.argv[4]) if len(sys.argv) > 4 else 64
replicas = int(sys.argv[5]) if len(sys.argv) > 5 else 1
os.makedirs(d + "/storage")
procs = []
for r in range(replicas):
    p = subprocess.Popen([v, "serve", "--storage", d + "/storage", "--database", url, "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0"], stdout=subprocess.PIPE, text=True)
    procs.append(p)
    for line in p.stdout:
        m = re.search(r"HTTP on 127.0.0.1:(\d+)", line)
        if m and r == 0: port = m.group(1)
        if "ready" in line: break
base = "http://127.0.0.1:" + port
subprocess.run([v, "generate", "sphere", "--triangles", "2000", "-o", d + "/sphere.ply"], check=True, capture_output=True)
req = urllib.request.Request(base + "/v1/scenes?name=sphere.ply", data=open(d + "/sphere.ply", "rb").read(), method="PUT")
scene = json.load(urllib.request.urlopen(req))["id"]
def job(tiles):
    body = {"scene_id": scene, "width": 128, "height": 128, "spp": spp, "tiles": tiles}
    r = urllib.request.Request(base + "/v1/jobs", data=json.dumps(body).encode(), headers={"content-type": "application/json"}, method="POST")
    t0 = time.time(); jid = json.load(urllib.request.urlopen(r))["id"]
    while True:
        j = json.load(urllib.request.urlopen(base + "/v1/jobs/" + jid))
        if j["state"] in ("JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED"): break
        time.sleep(0.01)
    return time.time() - t0, j["state"]
job([1, 1])  # warm: opens the scene
for tiles in ([1, 1], [2, 2], [4, 4], [8, 8]):
    times = sorted(job(tiles)[0] for _ in range(3))
    n = tiles[0] * tiles[1]
    print(f"{replicas} replica(s), tiles {tiles[0]}x{tiles[1]}: median job time {times[1]:.3f} s over 3 runs ({n} tasks)")
for p in procs: p.terminate()
for p in procs: p.wait()
PY
runuser -u nobody -- $B/pg_ctl -D $D/data -m immediate stop >/dev/null
rm -rf $D
