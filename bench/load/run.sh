#!/usr/bin/env bash
# Load test of `vastray serve` (issue 5): ghz (gRPC) and wrk (HTTP) against a server on loopback
# holding a multi-million-triangle scene. Writes docs/generated/load_test.md.
#
#   bash bench/load/run.sh [BUILD_DIR]          (tools: bash scripts/install-bench-tools.sh)
#
# Phase A, front ends, queue and store: a --paused server (jobs are accepted and stored, none
#   renders), so the figures are those of the front ends, validation and the SQLite job store
#   (synchronous=FULL: one fsync per accepted job), not of lavapipe.
#   ghz SubmitJob, ghz GetJob, wrk GET /v1/jobs/{id}, wrk POST /v1/jobs.
# Phase B, overload: a fresh server that renders (--max-queue $OVERLOAD_QUEUE). One small job runs
#   to the end (its stats, RSS after a render), then a long job keeps the renderer busy on every
#   core while the queue is filled; ghz SubmitJob and wrk POST /v1/jobs then meet a full queue and
#   must get RESOURCE_EXHAUSTED / 429 at once (timeouts are counted; the client limit is
#   $CLIENT_TIMEOUT).
# Device memory is the service's own figure: the jobs' stats.peak_device_bytes and /metrics
# (vastray_device_memory_peak_bytes, vastray_device_memory_budget_bytes), read after the small job
# and at the end of phase B. As a cross-check, `vastray render --stats-json` renders the small job
# again from the package the server stored, at the server's budget.
#
# Knobs (defaults below): TRIANGLES GHZ_N GHZ_C WRK_DURATION WRK_C WRK_T OVERLOAD_QUEUE
# CLIENT_TIMEOUT JOB_SIZE BUSY_SIZE BUSY_SPP OUT_FILE KEEP_WORK=1 (keep the temporary folder).
set -euo pipefail

build=${1:-build}
vastray=$(realpath "$build/vastray")
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
triangles=${TRIANGLES:-2000000}
ghz_n=${GHZ_N:-2000}
ghz_c=${GHZ_C:-8}
wrk_duration=${WRK_DURATION:-10s}
wrk_c=${WRK_C:-8}
wrk_t=${WRK_T:-2}
overload_queue=${OVERLOAD_QUEUE:-8}
client_timeout=${CLIENT_TIMEOUT:-5s}
job_size=${JOB_SIZE:-16}
busy_size=${BUSY_SIZE:-512}
busy_spp=${BUSY_SPP:-64}
out=${OUT_FILE:-$root/docs/generated/load_test.md}
ghz=${GHZ:-$(command -v ghz || echo /usr/local/bin/ghz)}
wrk=${WRK:-$(command -v wrk || echo /usr/bin/wrk)}

for tool in "$ghz" "$wrk" curl python3; do
  command -v "$tool" > /dev/null || { echo "bench/load: $tool not found (bash scripts/install-bench-tools.sh)" >&2; exit 1; }
done
[ -x "$vastray" ] || { echo "bench/load: $vastray not built" >&2; exit 1; }

work=$(mktemp -d /tmp/vastray-load.XXXXXX)
res=$work/results
mkdir -p "$res"
: > "$res/commands.txt"
server_pid=""
phase=""

log() { echo "[load $(date -u +%H:%M:%S)] $*" >&2; }
# Runs a command and records it (the report prints them with $WORK, $GRPC, $HTTP, $SCENE, $JOB).
quote() {
  local out="" a
  for a in "$@"; do
    if [[ $a =~ ^[A-Za-z0-9_./:=@%+,-]+$ ]]; then out+="$a "; else out+="'${a//\'/\'\\\'\'}' "; fi
  done
  printf '%s\n' "${out% }"
}
run() {
  quote "$@" >> "$res/commands.txt"
  "$@"
}

stop_server() {
  [ -n "$server_pid" ] || return 0
  if kill -0 "$server_pid" 2> /dev/null; then
    grep -E '^(VmHWM|VmRSS)' "/proc/$server_pid/status" > "$res/$phase.rss" || true
    local t0 t1 rc=0
    t0=$(date +%s.%N)
    kill -TERM "$server_pid"
    wait "$server_pid" || rc=$?
    t1=$(date +%s.%N)
    echo "$rc $(python3 -c "print(f'{$t1 - $t0:.3f}')")" > "$res/$phase.exit"
  fi
  server_pid=""
}

cleanup() {
  stop_server
  if [ "${KEEP_WORK:-0}" = 1 ]; then log "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

start_server() {  # phase, extra flags...
  phase=$1
  shift
  echo "$(quote "$vastray" serve --data-dir "$work/$phase" --grpc 127.0.0.1:0 --http 127.0.0.1:0 "$@") &" \
    >> "$res/commands.txt"
  "$vastray" serve --data-dir "$work/$phase" --grpc 127.0.0.1:0 --http 127.0.0.1:0 "$@" \
    > "$res/$phase.server.out" 2> "$res/$phase.server.err" &
  server_pid=$!
  for _ in $(seq 1200); do
    grep -q 'ready' "$res/$phase.server.out" 2> /dev/null && break
    kill -0 "$server_pid" 2> /dev/null || { cat "$res/$phase.server.err" >&2; exit 1; }
    sleep 0.1
  done
  grpc=$(sed -n 's/.*gRPC on //p' "$res/$phase.server.out")
  http=$(sed -n 's/.*HTTP on //p' "$res/$phase.server.out")
  [ -n "$grpc" ] && [ -n "$http" ] || { echo "bench/load: server did not start" >&2; exit 1; }
  echo "$grpc" > "$res/$phase.grpc"
  echo "$http" > "$res/$phase.http"
  log "phase $phase: server $server_pid, gRPC $grpc, HTTP $http"
}

upload() {  # -> $scene (id); the scene JSON and curl's timing in results/
  run curl -sS --fail-with-body --max-time 1800 -o "$res/$phase.scene.json" \
    -w '%{http_code} %{time_total}\n' -T "$work/city.ply" "http://$http/v1/scenes?name=city.ply" \
    > "$res/$phase.upload"
  scene=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["id"])' "$res/$phase.scene.json")
  log "uploaded scene $scene: $(cat "$res/$phase.upload")"
}

submit_http() {  # width height spp -> prints the job id; the answer in results/$phase.submit.N.json
  local n
  n=$(ls "$res" | grep -c "^$phase.submit.*.json$" || true)
  local f="$res/$phase.submit.$n.json"
  curl -sS -o "$f" -H 'Content-Type: application/json' \
    -d "{\"scene_id\": \"$scene\", \"width\": $1, \"height\": $2, \"spp\": $3}" "http://$http/v1/jobs" \
    -w '%{http_code} %{time_total}\n' > "$f.code"
  python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get("id", ""))' "$f"
}

job_state() {
  curl -sS "http://$http/v1/jobs/$1" | python3 -c 'import json,sys; print(json.load(sys.stdin)["state"])'
}

ghz_call() {  # name method data [ghz flags...]
  local name=$1 method=$2 data=$3
  shift 3
  log "ghz $method ($name)"
  # Server reflection, not --proto: ghz 0.93's parser refuses proto3 `optional` fields.
  run "$ghz" --insecure --call "vastray.v1.RenderService.$method" -d "$data" --timeout "$client_timeout" \
    --format json -o "$res/$phase.ghz.$name.json" "$@" "$grpc" || true
  [ -s "$res/$phase.ghz.$name.json" ] || { echo "bench/load: ghz wrote nothing" >&2; exit 1; }
}

wrk_call() {  # name url [env assignments for the Lua script]
  local name=$1 url=$2
  shift 2
  log "wrk $url ($name)"
  run env "$@" "$wrk" -t "$wrk_t" -c "$wrk_c" -d "$wrk_duration" --timeout "$client_timeout" --latency \
    -s "$here/wrk.lua" "$url" > "$res/$phase.wrk.$name.txt" 2>&1 || true
}

metrics() { curl -sS "http://$http/metrics" > "$res/$phase.metrics.$1.txt"; }

uname -a > "$res/uname"
cat /proc/loadavg > "$res/loadavg.start"
date -u +%Y-%m-%dT%H:%M:%SZ > "$res/date"
{ go_bin=$(command -v go || echo /usr/local/go/bin/go)
  "$go_bin" version -m "$ghz" 2> /dev/null | awk '$1 == "mod" {print $3; exit}' | grep . || "$ghz" --version; } \
  > "$res/ghz.version" 2>&1 || true
"$wrk" -v 2>&1 | head -1 > "$res/wrk.version" || true
{ vulkaninfo --summary 2> /dev/null || true; } | sed -n 's/^\s*deviceName\s*=\s*//p' > "$res/vulkan.devices"
git -C "$root" rev-parse --short HEAD > "$res/git" 2> /dev/null || echo unknown > "$res/git"

log "generating city, $triangles triangles"
run "$vastray" generate city --triangles "$triangles" --seed 1 -o "$work/city.ply" > "$res/generate.txt"

# ---------------------------------------------------------------- phase A: front ends, queue, store
start_server A --paused --max-queue 1000000
upload
grep -E '^(VmHWM|VmRSS)' "/proc/$server_pid/status" > "$res/A.rss.after_upload" || true
metrics start
# Three GETs of one job on one keep-alive connection (curl reuses it): time of each.
u="http://$http/v1/jobs/$(submit_http "$job_size" "$job_size" 1)"
run curl -sS -o /dev/null -o /dev/null -o /dev/null \
  -w '%{num_connects} %{time_starttransfer} %{time_total}\n' "$u" "$u" "$u" > "$res/A.keepalive.txt"
# A cancel sent as `curl -X POST` (no body, so no Content-Length): its answer and time, and the
# job's state afterwards.
probe=$(submit_http "$job_size" "$job_size" 1)
run curl -sS -i -X POST -o "$res/A.cancel_nobody.txt" -w '%{http_code} %{time_total}\n' \
  "http://$http/v1/jobs/$probe:cancel" > "$res/A.cancel_nobody.code" || true
job_state "$probe" > "$res/A.cancel_nobody.state"
first_job=$(submit_http "$job_size" "$job_size" 1)
echo "$first_job" > "$res/A.job"
job_body="{\"scene_id\": \"$scene\", \"width\": $job_size, \"height\": $job_size, \"spp\": 1}"
ghz_call submit SubmitJob "$job_body" -n "$ghz_n" -c "$ghz_c" --connections 1
ghz_call get GetJob "{\"id\": \"$first_job\"}" -n "$((ghz_n * 2))" -c "$ghz_c" --connections 1
wrk_call get "http://$http/v1/jobs/$first_job"
wrk_call submit "http://$http/v1/jobs" "SCENE_ID=$scene" "JOB_WIDTH=$job_size" "JOB_HEIGHT=$job_size" JOB_SPP=1
metrics end
stop_server

# ---------------------------------------------------------------- phase B: a full queue, renderer busy
start_server B --max-queue "$overload_queue"
echo "$overload_queue" > "$res/B.max_queue"
upload
small=$(submit_http "$job_size" "$job_size" 1)
log "small job $small: waiting for it to finish"
for _ in $(seq 3000); do
  state=$(job_state "$small")
  case $state in JOB_STATE_SUCCEEDED | JOB_STATE_FAILED | JOB_STATE_CANCELLED) break ;; esac
  sleep 0.2
done
curl -sS "http://$http/v1/jobs/$small" > "$res/B.small.json"
grep -E '^(VmHWM|VmRSS)' "/proc/$server_pid/status" > "$res/B.rss.after_small" || true
metrics after_small

busy=$(submit_http "$busy_size" "$busy_size" "$busy_spp")
echo "$busy" > "$res/B.busy"
for _ in $(seq 600); do [ "$(job_state "$busy")" != JOB_STATE_QUEUED ] && break; sleep 0.1; done
job_state "$busy" > "$res/B.busy.state.before"
log "busy job $busy: $(cat "$res/B.busy.state.before"); filling the queue"
queued=()
for _ in $(seq "$overload_queue"); do queued+=("$(submit_http "$job_size" "$job_size" 1)"); done
# One more: must be 429 at once (its headers and body recorded as they came).
curl -sS -i -o "$res/B.first_429.txt" -w '%{http_code} %{time_total}\n' -H 'Content-Type: application/json' \
  -d "$job_body" "http://$http/v1/jobs" > "$res/B.first_429.code"
metrics full
ghz_call submit SubmitJob "$job_body" -n "$ghz_n" -c "$((ghz_c * 2))" --connections 2
ghz_call get GetJob "{\"id\": \"$busy\"}" -n "$ghz_n" -c "$ghz_c" --connections 1
wrk_call submit "http://$http/v1/jobs" "SCENE_ID=$scene" "JOB_WIDTH=$job_size" "JOB_HEIGHT=$job_size" JOB_SPP=1
job_state "$busy" > "$res/B.busy.state.after"
metrics end
grep -E '^(VmHWM|VmRSS)' "/proc/$server_pid/status" > "$res/B.rss.before_cancel" || true
log "cancelling the queue, then the busy job"
cancel() {
  echo "$1 $(curl -sS -o /dev/null -w '%{http_code} %{time_total}' -H 'Content-Type: application/json' \
    -d '{"reason": "load test done"}' "http://$http/v1/jobs/$1:cancel")" >> "$res/B.cancel.txt" || true
}
for id in "${queued[@]}"; do cancel "$id"; done
t0=$(date +%s.%N)
cancel "$busy"
# A cancelled streaming render stops at its next ray stream: time until the worker is idle
# (vastray_jobs_running = 0) from the busy job's cancel request, so that SIGTERM below does not
# wait for it.
running=1
for _ in $(seq 1800); do
  running=$(curl -sS "http://$http/metrics" | awk '$1 == "vastray_jobs_running" {print $2}')
  [ "$running" = 0 ] && break
  sleep 0.1
done
t1=$(date +%s.%N)
echo "$running $(python3 -c "print(f'{$t1 - $t0:.2f}')")" > "$res/B.cancel_to_idle"
log "worker idle after the cancel: $(cat "$res/B.cancel_to_idle")"
# Jobs accepted while the queue had room again (if the busy job ended during the phase).
curl -sS "http://$http/v1/jobs?state=JOB_STATE_QUEUED&page_size=1000" > "$res/B.queued_left.json"
python3 -c 'import json,sys; [print(j["id"]) for j in json.load(open(sys.argv[1])).get("jobs", [])]' \
  "$res/B.queued_left.json" | while read -r id; do
  curl -sS -o /dev/null -H 'Content-Type: application/json' -d '{}' "http://$http/v1/jobs/$id:cancel" || true
done
package="$work/B/scenes/$scene.vast"
log "stopping the server (SIGTERM)"
stop_server

# ---------------------------------------------------------------- cross-check of the device memory
# The service's figures are in B.small.json (stats) and B.metrics.*.txt; the same job through
# `vastray render` at the budget the server reported must give the same peak.
budget_bytes=$(awk '$1 == "vastray_device_memory_budget_bytes" {print $2}' "$res/B.metrics.end.txt")
log "device memory cross-check: vastray render of the stored package (budget ${budget_bytes:-?} bytes)"
run "$vastray" render "$package" -o "$work/small.png" --resolution "${job_size}x${job_size}" --spp 1 \
  --memory-budget "${budget_bytes:-4GiB}" --host-cache 2GiB --progress none --stats-json "$res/render.stats.json" \
  > "$res/render.txt" 2>&1 || true

mkdir -p "$(dirname "$out")"
python3 "$here/report.py" "$res" "$work" > "$out"
log "wrote $out"
cat "$out"
