-- wrk script for bench/load/run.sh.
--   SCENE_ID set: POST the job body below to the URL (POST /v1/jobs); unset: plain GET.
--   JOB_WIDTH/JOB_HEIGHT/JOB_SPP: job size (default 16x16, 1 spp).
-- Counts responses by HTTP status in every thread and prints, after wrk's own summary, one
-- line "WRK_JSON {...}" with requests, duration, latency percentiles (all responses) and
-- wrk's socket errors (connect/read/write/timeout) for bench/load/report.py.
local scene = os.getenv("SCENE_ID")
if scene and scene ~= "" then
  wrk.method = "POST"
  wrk.body = string.format('{"scene_id": "%s", "width": %d, "height": %d, "spp": %d}', scene,
    tonumber(os.getenv("JOB_WIDTH") or "16"), tonumber(os.getenv("JOB_HEIGHT") or "16"),
    tonumber(os.getenv("JOB_SPP") or "1"))
  wrk.headers["Content-Type"] = "application/json"
end

local threads = {}

function setup(thread)
  table.insert(threads, thread)
end

function init(args)
  statuses = {}
end

function response(status, headers, body)
  local key = tostring(status)
  statuses[key] = (statuses[key] or 0) + 1
end

function done(summary, latency, requests)
  local total = {}
  for _, thread in ipairs(threads) do
    local counts = thread:get("statuses")
    for code, n in pairs(counts) do
      total[code] = (total[code] or 0) + n
    end
  end
  local parts = {}
  for code, n in pairs(total) do
    table.insert(parts, string.format('"%s": %d', code, n))
  end
  local e = summary.errors
  io.write(string.format(
    'WRK_JSON {"requests": %d, "duration_us": %d, "bytes": %d, "p50_us": %d, "p90_us": %d, ' ..
    '"p99_us": %d, "max_us": %d, "mean_us": %.1f, "errors": {"connect": %d, "read": %d, ' ..
    '"write": %d, "status": %d, "timeout": %d}, "statuses": {%s}}\n',
    summary.requests, summary.duration, summary.bytes, latency:percentile(50),
    latency:percentile(90), latency:percentile(99), latency.max, latency.mean, e.connect, e.read,
    e.write, e.status, e.timeout, table.concat(parts, ", ")))
end
