#include "OpenApi.h"

#include <nlohmann/json.hpp>

#include "OpenApiSchemas.h"
#include "ProtoComments.h"
#include "vastray/server/ServiceStatus.h"

namespace vastray::server {
namespace {

using nlohmann::json;

json jsonContent(const std::string& protoMessage) {
    return {{"application/json", {{"schema", openApiSchemaRef("vastray.v1." + protoMessage)}}}};
}

json ok(const char* description, const std::string& protoMessage) {
    return {{"description", description}, {"content", jsonContent(protoMessage)}};
}

json plainText(const char* description) {
    return {{"description", description}, {"content", {{"text/plain", {{"schema", {{"type", "string"}}}}}}}};
}

json errorRef(const char* name) { return {{"$ref", "#/components/responses/" + std::string(name)}}; }

// Error responses every authenticated route can give, plus `codes` (HTTP status -> name in
// components/responses).
json responses(json success, std::initializer_list<std::pair<const char*, const char*>> codes) {
    json r = std::move(success);
    r["401"] = errorRef("Unauthorized");
    r["500"] = errorRef("Internal");
    for (const auto& [status, name] : codes) r[status] = errorRef(name);
    return r;
}

json requestBody(const std::string& protoMessage, bool required = true) {
    return {{"required", required}, {"content", jsonContent(protoMessage)}};
}

json idParameter(const char* what) {
    return {{"name", "id"},
            {"in", "path"},
            {"required", true},
            {"description", what},
            {"schema", {{"type", "string"}}}};
}

json queryParameter(const char* name, json schema, const std::string& description, bool required = false) {
    return {{"name", name}, {"in", "query"}, {"required", required}, {"description", description}, {"schema", schema}};
}

json pageParameters(const std::string& listRequest) {
    return {queryParameter("page_size", {{"type", "integer"}, {"minimum", 0}, {"maximum", 1000}},
                           protoComment("vastray.v1." + listRequest + ".page_size")),
            queryParameter("page_token", {{"type", "string"}},
                           "next_page_token of the previous page; absent for the first page.")};
}

// An operation: `rpc` ("SceneService.GetScene") names the gRPC method it equals; its comment
// leads the description.
json operation(const char* operationId, const char* tag, const char* summary, const std::string& rpc,
               const std::string& notes = "") {
    std::string description = protoComment("vastray.v1." + rpc);
    if (!notes.empty()) description += (description.empty() ? "" : "\n\n") + notes;
    description += (description.empty() ? "" : "\n\n") + ("gRPC: `vastray.v1." + rpc + "`.");
    return {{"operationId", operationId}, {"tags", {tag}}, {"summary", summary}, {"description", description}};
}

void addScenePaths(json& p) {
    json upload = operation("uploadScene", "scenes", "Upload a scene", "SceneService.UploadScene",
                            "The body is the file's bytes. Multipart bodies are refused (415).");
    upload["parameters"] = {queryParameter("name", {{"type", "string"}},
                                           protoComment("vastray.v1.UploadSceneRequest.name"), true),
                            queryParameter("async", {{"type", "boolean"}},
                                           protoComment("vastray.v1.UploadSceneRequest.async"))};
    upload["requestBody"] = {
        {"required", true},
        {"content", {{"application/octet-stream", {{"schema", {{"type", "string"}, {"contentMediaType", "application/octet-stream"}}}}}}}};
    json queued = ok("?async=true and new content: the scene's id, name and upload_bytes, and import_job_id.", "Scene");
    queued["headers"]["Location"] = {{"description", "/v1/jobs/{id} of the import job"},
                                     {"schema", {{"type", "string"}}}};
    upload["responses"] = responses({{"200", ok("The stored scene (the existing one for known content).", "Scene")},
                                     {"202", queued}},
                                    {{"400", "BadRequest"}, {"413", "PayloadTooLarge"}, {"415", "UnsupportedMediaType"},
                                     {"503", "Unavailable"}});
    p["/v1/scenes"]["put"] = upload;

    json list = operation("listScenes", "scenes", "List scenes", "SceneService.ListScenes");
    list["parameters"] = pageParameters("ListScenesRequest");
    list["responses"] = responses({{"200", ok("A page of scenes.", "ListScenesResponse")}}, {{"400", "BadRequest"}});
    p["/v1/scenes"]["get"] = list;

    json find = operation("findMissingScenes", "scenes", "Which digests are unknown", "SceneService.FindMissing");
    find["requestBody"] = requestBody("FindMissingRequest");
    find["responses"] = responses({{"200", ok("The unknown digests.", "FindMissingResponse")}},
                                  {{"400", "BadRequest"}, {"411", "LengthRequired"}, {"413", "PayloadTooLarge"},
                                   {"415", "UnsupportedMediaType"}});
    p["/v1/scenes:findMissing"]["post"] = find;

    const json sceneId = idParameter("The scene's id (lowercase hex SHA-256 of its upload).");
    json get = operation("getScene", "scenes", "Get a scene", "SceneService.GetScene");
    get["responses"] = responses({{"200", ok("The scene.", "Scene")}}, {{"404", "NotFound"}});
    json remove = operation("deleteScene", "scenes", "Delete a scene", "SceneService.DeleteScene");
    remove["responses"] =
        responses({{"200", ok("Deleted.", "DeleteSceneResponse")}}, {{"404", "NotFound"}, {"409", "Conflict"}});
    p["/v1/scenes/{id}"] = {{"parameters", {sceneId}}, {"get", get}, {"delete", remove}};
}

void addEnvironmentPaths(json& p) {
    json upload = operation("uploadEnvironment", "environments", "Upload an environment map",
                            "SceneService.UploadEnvironment",
                            "The body is the file's bytes. Multipart bodies are refused (415).");
    upload["parameters"] = {queryParameter("name", {{"type", "string"}},
                                           protoComment("vastray.v1.UploadEnvironmentRequest.name"), true)};
    upload["requestBody"] = {
        {"required", true},
        {"content", {{"application/octet-stream", {{"schema", {{"type", "string"}, {"contentMediaType", "application/octet-stream"}}}}}}}};
    upload["responses"] =
        responses({{"200", ok("The stored environment (the existing one for known content).", "Environment")}},
                  {{"400", "BadRequest"}, {"413", "PayloadTooLarge"}, {"415", "UnsupportedMediaType"},
                   {"503", "Unavailable"}});
    p["/v1/environments"]["put"] = upload;

    json list = operation("listEnvironments", "environments", "List environment maps", "SceneService.ListEnvironments");
    list["parameters"] = pageParameters("ListEnvironmentsRequest");
    list["responses"] =
        responses({{"200", ok("A page of environments.", "ListEnvironmentsResponse")}}, {{"400", "BadRequest"}});
    p["/v1/environments"]["get"] = list;

    const json environmentId = idParameter("The environment's id (lowercase hex SHA-256 of its upload).");
    json get = operation("getEnvironment", "environments", "Get an environment map", "SceneService.GetEnvironment");
    get["responses"] = responses({{"200", ok("The environment.", "Environment")}}, {{"400", "BadRequest"}, {"404", "NotFound"}});
    json remove = operation("deleteEnvironment", "environments", "Delete an environment map",
                            "SceneService.DeleteEnvironment");
    remove["responses"] = responses({{"200", ok("Deleted.", "DeleteEnvironmentResponse")}},
                                    {{"400", "BadRequest"}, {"404", "NotFound"}, {"409", "Conflict"}});
    p["/v1/environments/{id}"] = {{"parameters", {environmentId}}, {"get", get}, {"delete", remove}};
}

json submitOperation() {
    json submit = operation("submitJob", "jobs", "Submit a render job", "RenderService.SubmitJob",
                            "Answers 202 with `Location: /v1/jobs/{id}` for a new job, 200 with the earlier job "
                            "for a known Idempotency-Key.");
    submit["parameters"] = {{{"name", "Idempotency-Key"},
                             {"in", "header"},
                             {"required", false},
                             {"description", protoComment("vastray.v1.SubmitJobRequest.request_id")},
                             {"schema", {{"type", "string"}, {"maxLength", 128}}}}};
    submit["requestBody"] = requestBody("SubmitJobRequest");
    json created = ok("Queued.", "Job");
    created["headers"]["Location"] = {{"description", "/v1/jobs/{id} of the new job"},
                                      {"schema", {{"type", "string"}}}};
    submit["responses"] = responses(
        {{"202", created}, {"200", ok("The job an earlier request with this Idempotency-Key created.", "Job")}},
        {{"400", "BadRequest"}, {"404", "NotFound"}, {"409", "Conflict"}, {"411", "LengthRequired"},
         {"413", "PayloadTooLarge"}, {"415", "UnsupportedMediaType"}, {"429", "TooManyRequests"},
         {"503", "Unavailable"}});
    return submit;
}

json resultOperation() {
    json result = operation("getJobResult", "jobs", "Download a job's image", "RenderService.GetResult",
                            "Range requests (`Range: bytes=a-b`) answer 206 with Content-Range. With `aov` or "
                            "`format=png`: an 8-bit PNG preview of one channel group for display (HTTP only; "
                            "mappings in docs/SERVICE.md, \"Result previews\").");
    result["parameters"] = {
        {{"name", "Range"},
         {"in", "header"},
         {"required", false},
         {"description", "Byte ranges of the file (RFC 9110)."},
         {"schema", {{"type", "string"}}}},
        queryParameter("aov",
                       {{"type", "string"},
                        {"enum", {"beauty", "depth", "normal", "albedo", "primid", "chunkid", "cost", "uv"}}},
                       "A PNG preview of this channel group (default beauty); AOVs the job did not render are "
                       "400."),
        queryParameter("format", {{"type", "string"}, {"enum", {"png"}}},
                       "png: a PNG preview (the beauty unless `aov` says otherwise); absent: the file as stored.")};
    const json image = {{"type", "string"}, {"contentMediaType", "application/octet-stream"}};
    const json content = {{"image/png", {{"schema", image}}}, {"image/x-exr", {{"schema", image}}}};
    result["responses"] = responses(
        {{"200", {{"description", "The whole image file, or the PNG preview."}, {"content", content}}},
         {"206", {{"description", "The requested bytes of the image file."}, {"content", content}}}},
        {{"400", "BadRequest"}, {"404", "NotFound"}, {"409", "Conflict"}, {"416", "RangeNotSatisfiable"}});
    return result;
}

void addJobPaths(json& p) {
    p["/v1/jobs"]["post"] = submitOperation();
    json list = operation("listJobs", "jobs", "List jobs", "RenderService.ListJobs");
    list["parameters"] = pageParameters("ListJobsRequest");
    list["parameters"].push_back(
        queryParameter("state", openApiSchemaRef("vastray.v1.JobState"), protoComment("vastray.v1.ListJobsRequest.state")));
    list["responses"] = responses({{"200", ok("A page of jobs.", "ListJobsResponse")}}, {{"400", "BadRequest"}});
    p["/v1/jobs"]["get"] = list;

    const json jobId = idParameter("The job's id (\"job-\" and 32 hex digits).");
    json get = operation("getJob", "jobs", "Get a job", "RenderService.GetJob");
    get["responses"] = responses({{"200", ok("The job.", "Job")}}, {{"404", "NotFound"}});
    p["/v1/jobs/{id}"] = {{"parameters", {jobId}}, {"get", get}};

    json cancel = operation("cancelJob", "jobs", "Cancel a job", "RenderService.CancelJob",
                            "The body is optional; its `id`, if any, is replaced by the path's.");
    cancel["requestBody"] = requestBody("CancelJobRequest", false);
    cancel["responses"] = responses({{"200", ok("The cancelled job.", "Job")}},
                                    {{"400", "BadRequest"}, {"404", "NotFound"}, {"409", "Conflict"}});
    p["/v1/jobs/{id}:cancel"] = {{"parameters", {jobId}}, {"post", cancel}};

    json watch =
        operation("watchJob", "jobs", "Watch a job (Server-Sent Events)", "RenderService.WatchJob",
                  "Server-Sent Events: each block is `event: KIND_SNAPSHOT|KIND_STATE_CHANGED|KIND_PROGRESS` "
                  "(the event's `kind`) and `data:` a JobEvent as JSON; a failed watch ends with an `error` "
                  "event whose data is the error body's `error` object.");
    watch["responses"] = responses(
        {{"200",
          {{"description", "A text/event-stream of JobEvent messages, ending after a final state."},
           {"content", {{"text/event-stream", {{"schema", {{"type", "string"}}}}}}}}}},
        {{"404", "NotFound"}});
    p["/v1/jobs/{id}/events"] = {{"parameters", {jobId}}, {"get", watch}};
    p["/v1/jobs/{id}/result"] = {{"parameters", {jobId}}, {"get", resultOperation()}};
}

void addOperationalPaths(json& p) {
    const json open = json::array();  // no authentication, whatever the server's token
    p["/healthz"]["get"] = {{"operationId", "healthz"}, {"tags", {"operations"}}, {"summary", "Liveness"},
                            {"security", open}, {"responses", {{"200", plainText("The process serves HTTP.")}}}};
    p["/readyz"]["get"] = {
        {"operationId", "readyz"}, {"tags", {"operations"}}, {"summary", "Readiness"}, {"security", open},
        {"responses", {{"200", plainText("Ready to take jobs.")}, {"503", plainText("Shutting down.")}}}};
    p["/metrics"]["get"] = {
        {"operationId", "metrics"}, {"tags", {"operations"}}, {"summary", "Prometheus metrics"},
        {"description", "Prometheus text exposition format 0.0.4; the metrics are listed in docs/SERVICE.md."},
        {"responses", responses({{"200", plainText("The metrics.")}}, {})}};
    p["/openapi.json"]["get"] = {
        {"operationId", "openapi"}, {"tags", {"operations"}}, {"summary", "This document"},
        {"responses",
         responses({{"200", {{"description", "OpenAPI 3.1 document."},
                             {"content", {{"application/json", {{"schema", {{"type", "object"}}}}}}}}}},
                   {})}};
}

json errorSchema() {
    json codes = json::array();
    for (StatusCode code : {StatusCode::Cancelled, StatusCode::InvalidArgument, StatusCode::NotFound,
                            StatusCode::AlreadyExists, StatusCode::ResourceExhausted, StatusCode::FailedPrecondition,
                            StatusCode::Internal, StatusCode::Unavailable, StatusCode::Unauthenticated})
        codes.push_back(statusCodeName(code));
    json error = {{"type", "object"}, {"required", {"code", "message"}}};
    error["properties"]["code"] = {
        {"type", "string"}, {"enum", codes}, {"description", "The gRPC canonical code name."}};
    error["properties"]["message"] = {
        {"type", "string"}, {"description", "What went wrong; a bad field's message starts with the field name."}};
    json schema = {{"type", "object"}, {"description", "Body of every error response."}, {"required", {"error"}}};
    schema["properties"]["error"] = error;
    return schema;
}

json errorResponses() {
    const json body = {{"application/json", {{"schema", {{"$ref", "#/components/schemas/Error"}}}}}};
    auto error = [&](const char* description) { return json{{"description", description}, {"content", body}}; };
    json tooMany = error("The job queue is full (RESOURCE_EXHAUSTED); try again after Retry-After seconds.");
    tooMany["headers"]["Retry-After"] = {{"schema", {{"type", "integer"}}}, {"description", "Seconds to wait."}};
    json unauthorized = error("Missing or wrong bearer token (UNAUTHENTICATED).");
    unauthorized["headers"]["WWW-Authenticate"] = {{"schema", {{"type", "string"}}}};
    return {{"BadRequest", error("A bad field or parameter (INVALID_ARGUMENT); the message starts with its name.")},
            {"Unauthorized", unauthorized},
            {"NotFound", error("Unknown scene, environment or job (NOT_FOUND).")},
            {"Conflict", error("The scene, environment or job is in the wrong state, or a reused request_id "
                               "(FAILED_PRECONDITION).")},
            {"LengthRequired", error("A JSON body sent without Content-Length (chunked).")},
            {"PayloadTooLarge", error("The body is larger than the route takes, or the disk is full (RESOURCE_EXHAUSTED).")},
            {"UnsupportedMediaType", error("The Content-Type is not one the route takes.")},
            {"RangeNotSatisfiable", error("The Range lies outside the file, or has too many or overlapping ranges.")},
            {"TooManyRequests", tooMany},
            {"Internal", error("A storage or render failure on the server (INTERNAL).")},
            {"Unavailable", error("The server is shutting down (UNAVAILABLE).")}};
}

json tags() {
    return {{{"name", "scenes"},
             {"description", "Scenes are content-addressed: a scene's id is the lowercase hex SHA-256 of the "
                             "uploaded bytes (SceneService)."}},
            {{"name", "environments"},
             {"description", "Environment maps (.exr, .hdr) that jobs light scenes with, content-addressed as "
                             "scenes (SceneService)."}},
            {{"name", "jobs"}, {"description", "A job renders one stored scene to one image file (RenderService)."}},
            {{"name", "operations"}, {"description", "Health, metrics and this document."}}};
}

}  // namespace

std::string openApiDocument(bool authRequired) {
    json paths = json::object();
    addScenePaths(paths);
    addEnvironmentPaths(paths);
    addJobPaths(paths);
    addOperationalPaths(paths);
    json schemas = openApiProtoSchemas();
    schemas["Error"] = errorSchema();
    json document = {
        {"openapi", "3.1.0"},
        {"info",
         {{"title", "vastray render service"},
          {"version", "v1"},
          {"description",
           "HTTP front end of `vastray serve`. Bodies are the vastray.v1 proto messages in their proto3 JSON "
           "mapping (field names as in the .proto); every operation equals a gRPC method of the same "
           "service. Where the gRPC method answers a response message that wraps one resource "
           "(GetJobResponse's `job`, UploadSceneResponse's `scene`, WatchJobResponse's `event`), HTTP "
           "answers the resource itself."}}},
        {"tags", tags()},
        {"paths", paths},
        {"components",
         {{"schemas", schemas},
          {"responses", errorResponses()},
          {"securitySchemes",
           {{"bearerAuth",
             {{"type", "http"},
              {"scheme", "bearer"},
              {"description", "The token of --auth-token-file, as `Authorization: Bearer TOKEN`; required "
                              "by every route but /healthz and /readyz when the server has one."}}}}}}}};
    // Without a token the scheme is declared but no operation needs it (an empty requirement).
    document["security"] = authRequired ? json::array({{{"bearerAuth", json::array()}}}) : json::array({json::object()});
    return document.dump(2);
}

}  // namespace vastray::server
