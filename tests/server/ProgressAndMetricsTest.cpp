// What a watcher and a scraper see: progress events that never go back and carry chunk loads
// while the render pages; /metrics with histograms of job duration and queue wait, build info,
// process metrics and one status-code label scheme for both front ends.
#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <map>
#include <optional>
#include <cstring>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "ServerTestSupport.h"
#include "vastray/server/Metrics.h"
#include "vastray/v1/render_service.grpc.pb.h"

namespace vastray::test {
namespace {

uint64_t u64(const json& value) { return value.is_string() ? std::stoull(value.get<std::string>()) : value.get<uint64_t>(); }
// A uint64 field of an event, 0 when the JSON leaves it out.
uint64_t field(const json& event, const char* name) { return event.contains(name) ? u64(event[name]) : 0; }

class ProgressTest : public ServerTest, public ::testing::WithParamInterface<const char*> {};

// A job queued behind another on a different scene, watched from QUEUED to SUCCEEDED at a
// budget that splits it into many passes: no figure of any event is below the one before it,
// the pass count does not change once known, chunk loads show while passes remain (and, on the
// device, rays and the pool's bytes), and the last event has every pass done and the job's own
// figures.
TEST_P(ProgressTest, EventsAreMonotoneAndShowChunkLoadsWhileTheRenderRuns) {
    startServer({"--backend", GetParam(), "--memory-budget", "64MiB"});
    const std::filesystem::path terrain = dir_ / "terrain.ply";
    ASSERT_TRUE(generateToPly({GeneratorKind::Terrain, 3000, 2}, terrain.string()).isOk());
    auto put = http().Put("/v1/scenes?name=terrain.ply", readBytes(terrain), "application/octet-stream");
    ASSERT_TRUE(put && put->status == 200);
    json target = smallJob(uploadSphere()["id"]);
    json blocker = smallJob(json::parse(put->body)["id"]);
    blocker["width"] = blocker["height"] = 96;
    blocker["spp"] = std::string(GetParam()) == "embree" ? 128 : 8;  // Embree is ~50x faster here
    ASSERT_EQ(submit(blocker)->status, 202);
    target["width"] = target["height"] = 192;
    target["spp"] = 8;
    auto submitted = submit(target);
    ASSERT_EQ(submitted->status, 202);
    const std::string id = json::parse(submitted->body)["id"];

    const std::vector<json> events = watchEvents(http(), id);
    ASSERT_GE(events.size(), 3u);
    EXPECT_EQ(events.front()["state"], "JOB_STATE_QUEUED") << "the watch began behind the other job";
    const json job = getJob(id);
    const uint64_t passes = u64(job["stats"]["passes"]), loads = u64(job["stats"]["chunk_loads"]);
    EXPECT_GT(passes, 2u) << job.dump();
    EXPECT_GT(loads, 0u) << job.dump();
    const uint64_t rays = u64(job["stats"]["rays"]), deviceBytes = field(job["stats"], "peak_device_bytes");
    const bool device = std::string(GetParam()) == "vulkan";
    EXPECT_GT(rays, 0u);
    EXPECT_EQ(deviceBytes > 0, device) << job.dump();
    bool loadsWhilePassesRemain = false, raysWhilePassesRemain = false;
    std::set<uint64_t> passesSeen;
    for (size_t i = 0; i < events.size(); ++i) {
        const json& e = events[i];
        SCOPED_TRACE("event " + std::to_string(i) + ": " + e.dump());
        if (i > 0) {
            const json& p = events[i - 1];
            EXPECT_GE(e["percent"].get<double>(), p["percent"].get<double>());
            EXPECT_GE(u64(e["passes_done"]), u64(p["passes_done"]));
            EXPECT_GE(u64(e["chunk_loads"]), u64(p["chunk_loads"]));
            EXPECT_GE(field(e, "rays"), field(p, "rays"));
            EXPECT_GE(field(e, "device_bytes"), field(p, "device_bytes"));
            if (u64(p["passes_total"]) > 0) {
                EXPECT_EQ(u64(e["passes_total"]), u64(p["passes_total"]));
            }
        }
        EXPECT_LE(u64(e["passes_done"]), u64(e["passes_total"]));
        if (e["state"] == "JOB_STATE_RUNNING") {
            passesSeen.insert(u64(e["passes_done"]));
            if (u64(e["chunk_loads"]) > 0 && u64(e["passes_done"]) < passes) loadsWhilePassesRemain = true;
            if (field(e, "rays") > 0 && u64(e["passes_done"]) < passes) {
                raysWhilePassesRemain = true;
                EXPECT_EQ(field(e, "device_bytes"), deviceBytes) << "the pool is allocated when the render starts";
            }
            EXPECT_LE(field(e, "rays"), rays);
        }
    }
    EXPECT_TRUE(loadsWhilePassesRemain) << "chunk loads appeared only with the last pass";
    // Embree counts its rays when the render ends; the device wavefront after each tile.
    EXPECT_EQ(raysWhilePassesRemain, device) << "rays should show as passes finish on the device";
    EXPECT_GE(passesSeen.size(), 3u) << "passes should show as they finish";
    const json& last = events.back();
    EXPECT_EQ(last["state"], "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(last["percent"], 100);
    EXPECT_EQ(u64(last["passes_done"]), passes);
    EXPECT_EQ(u64(last["passes_total"]), passes);
    EXPECT_EQ(u64(last["chunk_loads"]), loads);
    EXPECT_EQ(field(last, "rays"), rays);
    EXPECT_EQ(field(last, "device_bytes"), deviceBytes);
    // A watch of the finished job: the same final figures at once.
    const std::vector<json> again = watchEvents(http(), id);
    ASSERT_EQ(again.size(), 1u);
    EXPECT_EQ(u64(again[0]["passes_done"]), passes);
    EXPECT_EQ(u64(again[0]["chunk_loads"]), loads);
}

INSTANTIATE_TEST_SUITE_P(Backends, ProgressTest, ::testing::Values("vulkan", "embree"),
                         [](const ::testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

// Prometheus text: sample "name{labels}" -> value, after checking that every line is a
// comment or a well-formed sample whose family has a TYPE line.
std::map<std::string, double> parseMetrics(const std::string& text) {
    std::map<std::string, double> samples;
    std::set<std::string> typed;
    const std::regex typeLine(R"(# TYPE ([a-zA-Z_:][a-zA-Z0-9_:]*) (counter|gauge|histogram)$)");
    const std::regex sampleLine(R"(([a-zA-Z_:][a-zA-Z0-9_:]*)(\{[^}]*\})? ([-+0-9.eE]+|\+Inf))");
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_match(line, m, typeLine)) {
            typed.insert(m[1]);
        } else if (line.rfind("# HELP ", 0) == 0) {
            continue;
        } else if (std::regex_match(line, m, sampleLine)) {
            std::string family = m[1];
            for (const char* suffix : {"_bucket", "_sum", "_count"})
                if (!typed.count(family) && family.size() > std::strlen(suffix) &&
                    family.compare(family.size() - std::strlen(suffix), std::string::npos, suffix) == 0)
                    family.resize(family.size() - std::strlen(suffix));
            EXPECT_TRUE(typed.count(family)) << "no TYPE before: " << line;
            samples[std::string(m[1]) + std::string(m[2])] = std::stod(m[3]);
        } else {
            ADD_FAILURE() << "not Prometheus text: '" << line << "'";
        }
    }
    return samples;
}

// The cumulative buckets of a histogram (in the order of the text) never go down and end at
// its count.
void expectHistogram(const std::string& text, const std::map<std::string, double>& m, const std::string& name,
                     const std::string& labels, double count) {
    const std::string prefix = labels.empty() ? "" : labels + ",";
    const std::string braces = labels.empty() ? "" : "{" + labels + "}";
    ASSERT_TRUE(m.count(name + "_count" + braces)) << name << braces;
    EXPECT_EQ(m.at(name + "_count" + braces), count) << name << braces;
    EXPECT_EQ(m.at(name + "_bucket{" + prefix + "le=\"+Inf\"}"), count) << name << braces;
    const std::string bucket = name + "_bucket{" + prefix + "le=\"";
    double previous = 0;
    int buckets = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (line.rfind(bucket, 0) == 0) {
            const double value = std::stod(line.substr(line.rfind(' ') + 1));
            EXPECT_GE(value, previous) << line;
            previous = value;
            ++buckets;
        }
    EXPECT_GE(buckets, 10) << name << braces;
}

TEST_F(ServerTest, MetricsHaveHistogramsBuildInfoProcessMetricsAndOneCodeScheme) {
    startServer({"--backend", "embree"});
    const auto started = std::chrono::system_clock::now();
    const std::string sceneId = uploadSphere()["id"];
    auto res = submit(smallJob(sceneId));
    ASSERT_EQ(res->status, 202);
    const json job = waitForState(json::parse(res->body)["id"], "JOB_STATE_SUCCEEDED");
    // A NOT_FOUND through each front end.
    EXPECT_EQ(http().Get("/v1/jobs/job-nope")->status, 404);
    auto channel = grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials());
    grpc::ClientContext context;
    v1::GetJobRequest get;
    get.set_id("job-nope");
    v1::GetJobResponse reply;
    EXPECT_EQ(v1::RenderService::NewStub(channel)->GetJob(&context, get, &reply).error_code(),
              grpc::StatusCode::NOT_FOUND);

    auto metrics = http().Get("/metrics");
    ASSERT_TRUE(metrics && metrics->status == 200);
    const auto m = parseMetrics(metrics->body);
    const double wall = std::chrono::duration<double>(std::chrono::system_clock::now() - started).count();

    expectHistogram(metrics->body, m, "vastray_job_duration_seconds", "state=\"SUCCEEDED\"", 1);
    expectHistogram(metrics->body, m, "vastray_job_duration_seconds", "state=\"FAILED\"", 0);
    expectHistogram(metrics->body, m, "vastray_job_queue_wait_seconds", "", 1);
    const double duration = m.at("vastray_job_duration_seconds_sum{state=\"SUCCEEDED\"}");
    EXPECT_GT(duration, 0);
    EXPECT_LT(duration, wall);
    EXPECT_GE(m.at("vastray_job_duration_seconds_sum{state=\"SUCCEEDED\"}"),
              job["stats"]["render_seconds"].get<double>() * 0.99)
        << "the job's duration includes its render";
    EXPECT_LT(m.at("vastray_job_queue_wait_seconds_sum"), wall);

    const std::string version = runVastray("--version").output;
    const std::regex buildInfo(R"re(\nvastray_build_info\{version="([^"]+)",build_type="[^"]*",compiler="[^"]+",grpc="[0-9.]+",protobuf="[0-9.]+"\} 1\n)re");
    std::smatch match;
    ASSERT_TRUE(std::regex_search(metrics->body, match, buildInfo)) << metrics->body;
    EXPECT_EQ("vastray " + match[1].str() + "\n", version);

    EXPECT_GT(m.at("process_cpu_seconds_total"), 0);
    EXPECT_GT(m.at("process_resident_memory_bytes"), 1e6);
    EXPECT_GE(m.at("process_virtual_memory_bytes"), m.at("process_resident_memory_bytes"));
    EXPECT_GT(m.at("process_open_fds"), 2);
    EXPECT_LE(m.at("process_open_fds"), m.at("process_max_fds"));
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    EXPECT_GT(m.at("process_start_time_seconds"), now - wall - 60);
    EXPECT_LE(m.at("process_start_time_seconds"), now + 1);

    // One scheme: canonical code names from both front ends, never an HTTP number.
    EXPECT_GE(m.at("vastray_requests_total{frontend=\"http\",code=\"NOT_FOUND\"}"), 1);
    EXPECT_GE(m.at("vastray_requests_total{frontend=\"grpc\",code=\"NOT_FOUND\"}"), 1);
    EXPECT_GE(m.at("vastray_requests_total{frontend=\"http\",code=\"OK\"}"), 3);
    EXPECT_FALSE(std::regex_search(metrics->body, std::regex(R"(code="[0-9]+")"))) << metrics->body;
}

// vastray_tasks_waiting reads the task store (a database query on replicas): however often
// /metrics is scraped, the query runs at most once a period; a failed query leaves the sample out
// until the next period rather than repeating a stale figure.
TEST(CachedGaugeTest, ComputesAtMostOncePerPeriodAndForgetsAFailure) {
    int computations = 0;
    std::optional<uint64_t> next = 4;
    server::CachedGauge gauge(std::chrono::seconds(1), [&] {
        ++computations;
        return next;
    });
    const auto t0 = server::CachedGauge::Clock::time_point{} + std::chrono::hours(1);
    EXPECT_EQ(gauge.read(t0), 4u);
    next = 7;
    for (int ms : {0, 1, 500, 999}) EXPECT_EQ(gauge.read(t0 + std::chrono::milliseconds(ms)), 4u) << ms;
    EXPECT_EQ(computations, 1) << "five reads within a second: one query";
    EXPECT_EQ(gauge.read(t0 + std::chrono::milliseconds(1000)), 7u);
    EXPECT_EQ(computations, 2);
    next = std::nullopt;
    EXPECT_EQ(gauge.read(t0 + std::chrono::milliseconds(2500)), std::nullopt) << "a failed query reads as none";
    next = 9;
    EXPECT_EQ(gauge.read(t0 + std::chrono::milliseconds(3000)), std::nullopt) << "and is not retried within the period";
    EXPECT_EQ(gauge.read(t0 + std::chrono::milliseconds(3500)), 9u);
    EXPECT_EQ(computations, 4);
}

// Scrapes from many threads at once (several Prometheus servers, or an adapter and a person)
// share one computation.
TEST(CachedGaugeTest, ConcurrentReadsShareOneComputation) {
    std::atomic<int> computations{0};
    server::CachedGauge gauge(std::chrono::hours(1), [&] {
        ++computations;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        return std::optional<uint64_t>(3);
    });
    std::vector<std::thread> readers;
    std::atomic<int> threes{0};
    for (int i = 0; i < 8; ++i) readers.emplace_back([&] { threes += gauge.read() == 3u ? 1 : 0; });
    for (auto& t : readers) t.join();
    EXPECT_EQ(computations.load(), 1);
    EXPECT_EQ(threes.load(), 8);
}

}  // namespace
}  // namespace vastray::test
