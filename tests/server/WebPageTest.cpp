// The web page's HTTP side: its embedded files at "/" (no token needed, CSP, caching) and the
// PNG previews of a result's channel groups (GET /v1/jobs/{id}/result?aov=...&format=png) that
// its AOV viewer shows. The page itself is driven in headless Chromium by web_page_test.py.
#include <array>
#include <cmath>
#include <fstream>

#include "ServerTestSupport.h"
#include "vastray/core/ImageFile.h"

namespace vastray::test {
namespace {

std::string messageOf(const httplib::Result& res) {
    auto body = json::parse(res ? res->body : "", nullptr, false);
    return body.is_object() && body.contains("error") ? body["error"].value("message", "") : "";
}

// A decoded 8-bit RGBA preview; values 0..255.
struct Preview {
    uint32_t width = 0, height = 0;
    std::vector<std::array<int, 4>> pixels;
    const std::array<int, 4>& at(uint32_t x, uint32_t y) const { return pixels[size_t(y) * width + x]; }
};

class WebPageTest : public ServerTest {
protected:
    std::string tokenFile() {
        const auto file = dir_ / "token";
        std::ofstream(file) << "web-token\n";
        return file.string();
    }

    // Renders the sphere at 32x24, 2 spp with `aovs`; the job's id once it SUCCEEDED.
    std::string renderSphere(const json& aovs) {
        const json scene = uploadSphere();
        json body = {{"scene_id", scene["id"]}, {"width", 32}, {"height", 24}, {"spp", 2}};
        if (!aovs.empty()) body["aovs"] = aovs;
        auto submitted = submit(body);
        EXPECT_TRUE(submitted && submitted->status == 202) << (submitted ? submitted->body : "no response");
        const std::string id = json::parse(submitted->body)["id"];
        waitForState(id, "JOB_STATE_SUCCEEDED");
        return id;
    }

    httplib::Result preview(const std::string& id, const std::string& query) {
        return http().Get(("/v1/jobs/" + id + "/result?" + query).c_str());
    }

    Preview decode(const std::string& png, const std::string& name) {
        const auto path = dir_ / (name + ".png");
        std::ofstream(path, std::ios::binary) << png;
        auto channels = readImageChannels(path.string(), {"R", "G", "B", "A"});
        EXPECT_TRUE(channels) << channels.message();
        Preview out;
        if (!channels) return out;
        out.width = channels->width, out.height = channels->height;
        for (const auto& plane : channels->planes)
            EXPECT_EQ(plane.size(), size_t(out.width) * out.height) << name;
        out.pixels.resize(size_t(out.width) * out.height);
        for (size_t i = 0; i < out.pixels.size(); ++i)
            for (int c = 0; c < 4; ++c) out.pixels[i][c] = int(std::lround(channels->planes[c][i] * 255.0f));
        return out;
    }

    Preview fetchPreview(const std::string& id, const std::string& aov) {
        auto res = preview(id, "aov=" + aov + "&format=png");
        EXPECT_TRUE(res && res->status == 200) << aov << ": " << (res ? res->body : "no response");
        if (!res || res->status != 200) return {};
        EXPECT_EQ(res->get_header_value("Content-Type"), "image/png") << aov;
        Preview image = decode(res->body, aov);
        EXPECT_EQ(image.width, 32u) << aov;
        EXPECT_EQ(image.height, 24u) << aov;
        return image;
    }
};

TEST_F(WebPageTest, ThePageIsServedWithoutTheTokenWithOnlyLocalSources) {
    startServer({"--auth-token-file", tokenFile()});
    auto page = http().Get("/");
    ASSERT_TRUE(page);
    EXPECT_EQ(page->status, 200) << "the page asks for the token itself";
    EXPECT_EQ(page->get_header_value("Content-Type"), "text/html; charset=utf-8");
    const std::string csp = page->get_header_value("Content-Security-Policy");
    EXPECT_NE(csp.find("default-src 'none'"), std::string::npos) << csp;
    EXPECT_NE(csp.find("script-src 'self'"), std::string::npos) << csp;
    EXPECT_EQ(csp.find("http"), std::string::npos) << "no remote source: " << csp;
    EXPECT_NE(page->body.find("<script src=\"app.js\""), std::string::npos);
    EXPECT_EQ(page->body.find("://"), std::string::npos) << "no CDN or other remote URL in the page";
    EXPECT_EQ(page->body.find("<script>"), std::string::npos) << "no inline script (the CSP forbids it)";
    EXPECT_EQ(http().Get("/index.html")->body, page->body);

    for (const auto& [path, type] : {std::pair{"/app.js", "text/javascript; charset=utf-8"},
                                     std::pair{"/app.css", "text/css; charset=utf-8"}}) {
        auto file = http().Get(path);
        ASSERT_TRUE(file);
        EXPECT_EQ(file->status, 200) << path;
        EXPECT_EQ(file->get_header_value("Content-Type"), type) << path;
        EXPECT_GT(file->body.size(), 1000u) << path;
        EXPECT_EQ(file->body.find("://"), std::string::npos) << path << " names a remote URL";
    }
    EXPECT_NE(http().Get("/app.js")->body.find("Authorization"), std::string::npos)
        << "the compiled script sends the bearer token";

    // Caching: revalidation by ETag answers 304 without a body.
    const std::string etag = page->get_header_value("ETag");
    EXPECT_EQ(page->get_header_value("Cache-Control"), "no-cache");
    ASSERT_FALSE(etag.empty());
    auto again = http().Get("/", httplib::Headers{{"If-None-Match", etag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304);
    EXPECT_TRUE(again->body.empty());

    EXPECT_EQ(http().Get("/v1/jobs")->status, 401) << "the API still needs the token";
    EXPECT_EQ(http().Get("/app.ts")->status, 401) << "only the page's own files are open";
}

TEST_F(WebPageTest, EveryAovPreviewIsAPngOfTheImageSizeWithItsDocumentedMapping) {
    startServer();
    const std::string id = renderSphere({"depth", "normal", "albedo", "primid", "chunkid", "cost", "uv"});
    const Preview depth = fetchPreview(id, "depth");
    const Preview normal = fetchPreview(id, "normal");
    const Preview albedo = fetchPreview(id, "albedo");
    const Preview chunks = fetchPreview(id, "chunkid");
    const Preview cost = fetchPreview(id, "cost");
    ASSERT_EQ(depth.pixels.size(), 32u * 24u);
    // The default camera frames the sphere: the centre hits, the corners miss.
    const auto& miss = depth.at(0, 0);
    EXPECT_EQ(miss, (std::array<int, 4>{0, 0, 0, 255})) << "a miss is black in the depth preview";
    int brightest = 0, hits = 0;
    for (size_t i = 0; i < depth.pixels.size(); ++i) {
        const bool hit = depth.pixels[i][0] > 0;
        hits += hit;
        brightest = std::max(brightest, depth.pixels[i][0]);
        if (!hit) continue;
        EXPECT_GE(depth.pixels[i][0], 51) << "hits lie between 20 % grey (farthest) and white (nearest)";
        const auto& n = normal.pixels[i];
        const double x = n[0] / 127.5 - 1, y = n[1] / 127.5 - 1, z = n[2] / 127.5 - 1;
        EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0, 0.03)
            << "normal (n + 1) / 2 per component: unit length within 8-bit rounding, pixel " << i;
        EXPECT_EQ(albedo.pixels[i], albedo.at(16, 12)) << "one material: one albedo over the sphere";
        EXPECT_NE(chunks.pixels[i], (std::array<int, 4>{0, 0, 0, 255})) << "a hit has a chunk colour";
    }
    EXPECT_GT(hits, 100);
    EXPECT_EQ(brightest, 255) << "the nearest hit is white";
    EXPECT_EQ(normal.at(0, 0), (std::array<int, 4>{0, 0, 0, 255}));
    EXPECT_EQ(chunks.at(0, 0), (std::array<int, 4>{0, 0, 0, 255}));
    EXPECT_GT(albedo.at(16, 12)[0], 0);
    int white = 0;
    for (const auto& p : cost.pixels) white += p == std::array<int, 4>{255, 255, 255, 255};
    EXPECT_GE(white, 1) << "the costliest pixel is white on the heat ramp";
    // The sphere has no texture coordinates: its uv preview is black, hits and misses alike.
    const Preview uv = fetchPreview(id, "uv");
    ASSERT_EQ(uv.pixels.size(), depth.pixels.size());
    for (size_t i = 0; i < uv.pixels.size(); ++i) EXPECT_EQ(uv.pixels[i], (std::array<int, 4>{0, 0, 0, 255})) << i;

    // The beauty of the EXR, tone mapped, equals the PNG the same job renders without AOVs.
    const Preview beauty = fetchPreview(id, "beauty");
    const std::string plainId = renderSphere(json::array());
    auto plain = preview(plainId, "format=png");
    ASSERT_TRUE(plain && plain->status == 200);
    EXPECT_EQ(plain->body, result(plainId)) << "a PNG result is its own beauty preview";
    const Preview reference = decode(plain->body, "plain");
    ASSERT_EQ(reference.pixels.size(), beauty.pixels.size());
    for (size_t i = 0; i < beauty.pixels.size(); ++i)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(beauty.pixels[i][c], reference.pixels[i][c], 1) << i;
}

TEST_F(WebPageTest, BadPreviewParametersAreRefusedNamingTheParameter) {
    startServer();
    const std::string id = renderSphere({"depth"});
    auto bogus = preview(id, "aov=bogus&format=png");
    ASSERT_TRUE(bogus);
    EXPECT_EQ(bogus->status, 400);
    EXPECT_EQ(messageOf(bogus).rfind("aov: 'bogus': expected one of beauty, depth", 0), 0u)
        << messageOf(bogus);
    auto exr = preview(id, "aov=depth&format=exr");
    EXPECT_EQ(exr->status, 400);
    EXPECT_EQ(messageOf(exr).rfind("format: 'exr'", 0), 0u) << messageOf(exr);
    auto absent = preview(id, "aov=normal");
    EXPECT_EQ(absent->status, 400);
    EXPECT_EQ(messageOf(absent).rfind("aov: 'normal': job " + id + " was rendered without it", 0), 0u)
        << messageOf(absent);
    EXPECT_EQ(preview(id, "aov=depth")->status, 200) << "aov alone implies format=png";
    EXPECT_EQ(preview("job-00000000000000000000000000000000", "aov=depth")->status, 404);
    auto whole = http().Get(("/v1/jobs/" + id + "/result").c_str());
    EXPECT_EQ(whole->get_header_value("Content-Type"), "image/x-exr")
        << "without parameters: the file as stored";
}

}  // namespace
}  // namespace vastray::test
