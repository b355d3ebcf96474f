// /openapi.json against `openapi-spec-validator` (PyPI), which scripts/install-deps.sh installs
// into its own virtual environment at /opt/vastray/openapi-venv ($OPENAPI_SPEC_VALIDATOR names
// another binary). Without it these tests FAIL (never skip). A deliberately broken copy of the
// document is checked too, so that a validator that accepts anything cannot pass them.
#include <unistd.h>

#include <cstdlib>
#include <csignal>
#include <fstream>
#include <set>

#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

std::string findValidator() {
    if (const char* env = std::getenv("OPENAPI_SPEC_VALIDATOR"); env && *env) return env;
    return "/opt/vastray/openapi-venv/bin/openapi-spec-validator";
}

class OpenApiTest : public ServerTest {
protected:
    json document() {
        auto res = http().Get("/openapi.json");
        EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no response");
        return res ? json::parse(res->body, nullptr, false) : json();
    }

    // Exit code and output of the validator on `doc`, forced to OpenAPI 3.1 rules.
    CommandResult validate(const json& doc, const std::string& name) {
        const std::string validator = findValidator();
        if (::access(validator.c_str(), X_OK) != 0) {
            ADD_FAILURE() << validator << " is missing: run scripts/install-deps.sh";
            return {};
        }
        const auto path = dir_ / name;
        std::ofstream(path) << doc.dump(2);
        return runShell(validator + " --schema 3.1 " + path.string());
    }
};

TEST_F(OpenApiTest, DocumentValidatesAsOpenApi31WithAndWithoutAToken) {
    for (const bool withToken : {false, true}) {
        SCOPED_TRACE(withToken ? "with --auth-token-file" : "without a token");
        if (withToken) {
            server_.kill(SIGTERM);
            const auto tokenFile = dir_ / "token";
            std::ofstream(tokenFile) << "s3cret\n";
            token_ = "s3cret";
            startServer({"--auth-token-file", tokenFile.string()});
        } else {
            startServer();
        }
        const json doc = document();
        EXPECT_EQ(doc.value("openapi", ""), "3.1.0");
        const CommandResult run = validate(doc, "openapi.json");
        EXPECT_EQ(run.exitCode, 0) << run.output;
        EXPECT_NE(run.output.find("OK"), std::string::npos) << run.output;
        // With a token every operation needs the bearer scheme; without, none does.
        const json& security = doc["security"];
        ASSERT_TRUE(security.is_array() && security.size() == 1) << security.dump();
        EXPECT_EQ(security[0].contains("bearerAuth"), withToken) << security.dump();
    }
}

TEST_F(OpenApiTest, TheValidatorRejectsAnUndeclaredPathParameter) {
    startServer();
    json doc = document();
    ASSERT_TRUE(doc["paths"]["/v1/jobs/{id}"].contains("parameters"));
    doc["paths"]["/v1/jobs/{id}"].erase("parameters");
    const CommandResult run = validate(doc, "broken.json");
    EXPECT_NE(run.exitCode, 0) << run.output;
    EXPECT_NE(run.output.find("id"), std::string::npos) << run.output;
}

TEST_F(OpenApiTest, PathAndQueryParametersAreDeclared) {
    startServer();
    const json doc = document();
    for (const auto& [path, item] : doc["paths"].items()) {
        if (path.find("{id}") == std::string::npos) continue;
        ASSERT_TRUE(item.contains("parameters")) << path;
        EXPECT_EQ(item["parameters"][0]["name"], "id") << path;
        EXPECT_EQ(item["parameters"][0]["in"], "path") << path;
        EXPECT_EQ(item["parameters"][0]["required"], true) << path;
    }
    auto parameterNames = [&](const char* path, const char* method) {
        std::set<std::string> names;
        for (const json& p : doc["paths"][path][method]["parameters"]) names.insert(p["name"].get<std::string>());
        return names;
    };
    EXPECT_EQ(parameterNames("/v1/jobs", "get"), (std::set<std::string>{"page_size", "page_token", "state"}));
    EXPECT_EQ(parameterNames("/v1/scenes", "get"), (std::set<std::string>{"page_size", "page_token"}));
    EXPECT_EQ(parameterNames("/v1/scenes", "put"), (std::set<std::string>{"name", "async"}));
    EXPECT_EQ(parameterNames("/v1/environments", "put"), (std::set<std::string>{"name"}));
    EXPECT_EQ(parameterNames("/v1/environments", "get"), (std::set<std::string>{"page_size", "page_token"}));
    EXPECT_EQ(parameterNames("/v1/jobs", "post"), (std::set<std::string>{"Idempotency-Key"}));
    EXPECT_EQ(parameterNames("/v1/jobs/{id}/result", "get"), (std::set<std::string>{"Range", "aov", "format"}));
}

TEST_F(OpenApiTest, ErrorsAndAuthAreDescribed) {
    startServer();
    const json doc = document();
    EXPECT_EQ(doc["components"]["securitySchemes"]["bearerAuth"]["scheme"], "bearer");
    EXPECT_EQ(doc["components"]["schemas"]["Error"]["required"], json::array({"error"}));
    for (const auto& [path, item] : doc["paths"].items())
        for (const auto& [method, op] : item.items()) {
            if (method == "parameters") continue;
            const bool open = path == "/healthz" || path == "/readyz";
            EXPECT_EQ(op["responses"].contains("401"), !open) << method << " " << path;
            if (open) {
                EXPECT_EQ(op["security"], json::array()) << path;
            }
            EXPECT_TRUE(op.contains("operationId")) << method << " " << path;
        }
    // The errors the HTTP front end gives for each route (docs/SERVICE.md, "Status mapping").
    const json& submit = doc["paths"]["/v1/jobs"]["post"]["responses"];
    for (const char* code : {"200", "202", "400", "401", "404", "409", "411", "413", "415", "429", "500", "503"})
        EXPECT_TRUE(submit.contains(code)) << code;
    EXPECT_EQ(submit["429"]["$ref"], "#/components/responses/TooManyRequests");
    EXPECT_TRUE(doc["components"]["responses"]["TooManyRequests"]["headers"].contains("Retry-After"));
    EXPECT_TRUE(doc["paths"]["/v1/jobs/{id}/result"]["get"]["responses"].contains("416"));
    EXPECT_TRUE(doc["paths"]["/v1/scenes/{id}"]["delete"]["responses"].contains("409"));
    EXPECT_TRUE(doc["paths"]["/v1/environments/{id}"]["delete"]["responses"].contains("409"));
    EXPECT_TRUE(doc["paths"]["/v1/environments"]["put"]["responses"].contains("413"));
    EXPECT_EQ(doc["paths"]["/v1/jobs/{id}:cancel"]["post"]["requestBody"]["required"], false);
}

TEST_F(OpenApiTest, DescriptionsComeFromTheProtoComments) {
    startServer();
    const json doc = document();
    const json& schemas = doc["components"]["schemas"];
    EXPECT_EQ(schemas["Job"]["properties"]["progress"]["description"], "Percent done, 0..100.");
    EXPECT_EQ(schemas["SubmitJobRequest"]["properties"]["width"]["description"],
              "Image size in pixels, each side 1..16384. Required.");
    EXPECT_EQ(schemas["ListScenesResponse"]["properties"]["scenes"]["description"], "Oldest first.");
    // Multi-line comments are joined into one paragraph.
    EXPECT_EQ(schemas["Camera"]["description"],
              "A pinhole camera in world space. Absent from a request: the camera frames the whole scene.");
    const std::string jobState = schemas["JobState"].value("description", "");
    EXPECT_NE(jobState.find("`JOB_STATE_QUEUED`: Accepted and stored, waiting for the renderer."),
              std::string::npos)
        << jobState;
    // buf's lint rules: every value carries its enum's prefix (the JSON mapping writes the names).
    EXPECT_EQ(schemas["JobState"]["enum"],
              json({"JOB_STATE_UNSPECIFIED", "JOB_STATE_QUEUED", "JOB_STATE_RUNNING", "JOB_STATE_SUCCEEDED",
                    "JOB_STATE_FAILED", "JOB_STATE_CANCELLED"}));
    // HTTP answers the resource that gRPC's GetJobResponse wraps.
    EXPECT_EQ(doc["paths"]["/v1/jobs/{id}"]["get"]["responses"]["200"]["content"]["application/json"]["schema"],
              json({{"$ref", "#/components/schemas/Job"}}));
    const std::string kind = schemas["JobEvent_Kind"].value("description", "");
    EXPECT_NE(kind.find("`KIND_SNAPSHOT`: The state at the time the watch began."), std::string::npos)
        << kind;
    const std::string submit = doc["paths"]["/v1/jobs"]["post"].value("description", "");
    EXPECT_EQ(submit.rfind("Validates and queues a job.", 0), 0u) << submit;
    EXPECT_NE(submit.find("gRPC: `vastray.v1.RenderService.SubmitJob`"), std::string::npos) << submit;
    const std::string upload = doc["paths"]["/v1/scenes"]["put"]["parameters"][0].value("description", "");
    EXPECT_EQ(upload.rfind("File name of the upload;", 0), 0u) << upload;
}

}  // namespace
}  // namespace vastray::test
