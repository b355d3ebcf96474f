#pragma once
// What the zip upload tests share (ZipUploadTest, VolumeUploadTest): an HTTP PUT of a zip and
// the checks of a refused one.
#include <filesystem>
#include <string>
#include <vector>

#include "ServerTestSupport.h"
#include "ZipWriter.h"

namespace vastray::test {

class ZipUploadServerTest : public ServerTest {
protected:
    httplib::Result put(const std::filesystem::path& zip, const std::string& name, bool async = false) {
        return http().Put(("/v1/scenes?name=" + name + (async ? "&async=true" : "")).c_str(), readBytes(zip),
                          "application/zip");
    }

    // Uploads `entries` as NAME.zip; expects 400 whose message begins with the zip's name and
    // holds each of `phrases`; nothing may remain in the scratch folder or among the scenes.
    void expectZipRefused(const std::string& name, const std::vector<ZipEntry>& entries,
                          const std::vector<std::string>& phrases) {
        SCOPED_TRACE(name);
        const std::filesystem::path zip = dir_ / (name + ".zip");
        writeZip(zip, entries);
        auto res = put(zip, name + ".zip");
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 400) << res->body;
        const std::string message = json::parse(res->body)["error"]["message"];
        EXPECT_EQ(message.rfind("data: " + name + ".zip:", 0), 0u) << message;
        for (const std::string& phrase : phrases) EXPECT_NE(message.find(phrase), std::string::npos) << message;
        EXPECT_TRUE(std::filesystem::is_empty(dataDir() / "tmp")) << "scratch files left by " << name;
        EXPECT_TRUE(!std::filesystem::exists(dataDir() / "scenes") || std::filesystem::is_empty(dataDir() / "scenes"))
            << "a scene stored by " << name;
    }
};

}  // namespace vastray::test
