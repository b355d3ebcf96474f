// The scene half of the service: uploads (content-addressed by SHA-256), import of meshes
// into scene packages with the same streamer functions `vastray import` calls, listing and
// deletion.

#include <algorithm>
#include <cstring>

#include "JobRequest.h"
#include "VolumeManifest.h"
#include "ZipArchive.h"
#include "vastray/core/FilePath.h"
#include "vastray/server/Service.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::server {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kDiskCheckInterval = 16ull << 20;
constexpr size_t kMaxNameLength = 255;

// A name's extension without its dot, lower case ("" for none).
std::string extensionWithoutDot(const std::string& name) {
    const std::string ext = lowerExtension(name);
    return ext.empty() ? ext : ext.substr(1);
}

// The upload's format: a package by its magic bytes, a mesh by its name's extension, else
// by the magic of binary glTF or PLY. Empty when unknown.
std::string detectFormat(const std::string& name, const fs::path& file) {
    char head[8] = {};
    std::ifstream in(file, std::ios::binary);
    in.read(head, sizeof head);
    if (std::memcmp(head, "VASTRAY\0", 8) == 0) return "vast";
    const std::string ext = extensionWithoutDot(name);
    if (ext == "obj" || ext == "ply" || ext == "gltf" || ext == "glb" || ext == "zip") return ext;
    if (assimpReads(name)) return ext;  // STL, OFF, FBX, ... (kAssimpFormats)
    if (std::memcmp(head, "PK\x03\x04", 4) == 0) return "zip";
    if (std::memcmp(head, "glTF", 4) == 0) return "glb";
    if (std::memcmp(head, "ply", 3) == 0) return "ply";
    return "";
}

// Importer messages name the scratch file; the client knows its own file name.
std::string renamePath(std::string message, const std::string& from, const std::string& to) {
    for (size_t at; (at = message.find(from)) != std::string::npos;) message.replace(at, from.size(), to);
    return message;
}

bool isModelFile(const fs::path& path) {
    const std::string ext = extensionWithoutDot(path.filename().string());
    return ext == "obj" || ext == "ply" || ext == "gltf" || ext == "glb" || assimpReads(path.string());
}


// Imports the mesh file `mesh` into the scene package `package` with `volumes` beside it,
// adding the importer's warnings to `warnings`. Importer messages name scratch paths: each
// `renames` pair (scratch path or prefix, what the client calls it) is replaced in turn.
ServiceStatus importMeshFile(const fs::path& mesh, const fs::path& package,
                             const std::vector<std::pair<std::string, std::string>>& renames,
                             std::vector<std::string>& warnings, const ImportProgress& progress,
                             std::vector<Volume> volumes = {}) {
    auto imported = importMesh(mesh.string());
    if (imported) {
        if (progress) progress(10);
        warnings.insert(warnings.end(), imported->report.warnings.begin(), imported->report.warnings.end());
        PackageBuildOptions build;
        build.volumes = std::move(volumes);
        build.progress = Progress::Mode::None;
        build.degenerateDropped = imported->report.degenerateDropped;
        if (progress)
            build.observer = [&progress](uint64_t done, uint64_t total) {
                progress(10 + int(total ? 80 * std::min(done, total) / total : 80));
            };
        auto report = buildPackage(std::move(imported->mesh), package.string(), build);
        if (!report) imported = report.status();
        else warnings.insert(warnings.end(), report->warnings.begin(), report->warnings.end());
        if (report && progress) progress(95);
    }
    if (imported) return {};
    std::string message = imported.message();
    for (const auto& [from, to] : renames) message = renamePath(message, from, to);
    return invalidArgument("data", message);
}

// The one model of an extracted zip, or why there is not exactly one.
ServiceResult<fs::path> zipModel(const std::vector<fs::path>& files, const std::string& zipName) {
    std::vector<fs::path> models;
    for (const fs::path& f : files)
        if (isModelFile(f)) models.push_back(f);
    if (models.empty())
        return invalidArgument("data", zipName + ": holds no model (.gltf, .glb, .obj, .ply or " + assimpFormatList() + ")");
    if (models.size() > 1) {
        std::string list;
        for (size_t i = 0; i < models.size() && i < 5; ++i) list += (i ? ", " : "") + models[i].string();
        return invalidArgument("data", zipName + ": holds " + std::to_string(models.size()) + " models (" + list +
                                           (models.size() > 5 ? ", ..." : "") + "); a zip holds one");
    }
    return models.front();
}

// An importer's message about the model of a zip, which names the model by its file name
// ("car.obj: line 3 ..."), as "cars.zip:models/car.obj: line 3 ..."; others get the zip's name.
std::string inZip(const std::string& zipName, const fs::path& model, const std::string& message) {
    const std::string file = model.filename().string() + ": ";
    if (message.rfind(file, 0) == 0) return zipName + ":" + model.generic_string() + message.substr(file.size() - 2);
    return zipName + ": " + message;
}

void addVector(google::protobuf::RepeatedField<float>* to, const Vec3f& v) {
    to->Add(v.x);
    to->Add(v.y);
    to->Add(v.z);
}

// The package's cameras into Scene.cameras, so a client can offer them for scene_camera.
void addCameras(v1::Scene& scene, const std::vector<SceneCamera>& cameras) {
    for (size_t i = 0; i < cameras.size(); ++i) {
        v1::SceneCamera& camera = *scene.add_cameras();
        camera.set_name(cameras[i].name);
        camera.set_index(uint32_t(i));
        addVector(camera.mutable_eye(), cameras[i].camera.eye);
        addVector(camera.mutable_target(), cameras[i].camera.target);
        addVector(camera.mutable_up(), cameras[i].camera.up);
        camera.set_fov_y_degrees(cameras[i].camera.fovYDegrees);
    }
}

}  // namespace

// The volumes vastray-volumes.json lists (VolumeManifest.h), each .vdb read in a child process
// (VolumeReadOptions); .vdb files it does not list become warnings. Refusals name the zip and
// the manifest's element or the file in the zip ("cars.zip:fog.vdb: grid 'x': ...").
ServiceResult<std::vector<Volume>> zipVolumes(const fs::path& folder, const std::vector<fs::path>& files,
                                              const std::string& zipName, std::vector<std::string>& warnings) {
    auto manifest = readVolumeManifest(folder, files, zipName);
    if (!manifest) return manifest.status();
    warnings.insert(warnings.end(), manifest->warnings.begin(), manifest->warnings.end());
    VolumeReadOptions options;
    options.childProcess = true;
    auto volumes = readVolumes(manifest->sources, options);
    if (!volumes) return invalidArgument("data", volumes.message());
    return std::move(volumes).value();
}

// A zip: extracted into a scratch folder within the limits of ZipArchive.h (its uncompressed
// size within --max-upload and the free disk), its volumes read (zipVolumes) and its one model
// imported from there. The importers keep every file the model names (.bin, images, .mtl)
// inside the model's folder.
ServiceStatus Service::importZip(const std::string& name, const fs::path& file, const fs::path& package,
                                 std::vector<std::string>& warnings, const ImportProgress& progress) {
    const fs::path folder = objects_->scratchDir() / ("zip-" + randomHex(8));
    std::error_code error;
    if (!fs::create_directory(folder, error)) return internalError(folder.string() + ": cannot create");
    ZipLimits limits;
    const uint64_t available = objects_->availableBytes();
    const uint64_t disk = available > options_.diskReserveBytes ? available - options_.diskReserveBytes : 0;
    limits.maxTotalBytes = std::min(options_.maxUploadBytes, disk);
    ServiceStatus status;
    auto files = extractZip(file, folder, name, limits);
    if (!files) status = files.status();
    auto model = files ? zipModel(*files, name) : ServiceResult<fs::path>(status);
    if (status && !model) status = model.status();
    auto volumes = status ? zipVolumes(folder, *files, name, warnings) : ServiceResult<std::vector<Volume>>(status);
    if (status && !volumes) status = volumes.status();
    if (status) {
        status = importMeshFile(folder / *model, package, {{folder.string() + "/", ""}}, warnings, progress,
                                std::move(*volumes));
        if (!status && status.code() == StatusCode::InvalidArgument)
            status = invalidArgument("data", inZip(name, *model, status.message().substr(std::strlen("data: "))));
    }
    fs::remove_all(folder, error);
    return status;
}

SceneUpload::SceneUpload(Service& service, std::string name, fs::path file, uint64_t maxBytes)
    : service_(service), name_(std::move(name)), file_(std::move(file)), out_(file_, std::ios::binary),
      maxBytes_(maxBytes) {}

SceneUpload::~SceneUpload() {
    if (finished_) return;
    out_.close();
    std::error_code error;
    fs::remove(file_, error);
}

ServiceStatus SceneUpload::append(const void* data, size_t size) {
    if (finished_) return {StatusCode::FailedPrecondition, "upload already finished"};
    bytes_ += size;
    service_.metrics_.uploadBytes += size;
    if (bytes_ > maxBytes_)
        return {StatusCode::ResourceExhausted, name_ + ": upload exceeds the server's limit of " +
                                                   std::to_string(maxBytes_) + " bytes"};
    if (bytes_ >= nextDiskCheck_) {
        if (service_.objects_->availableBytes() < size + service_.options_.diskReserveBytes)
            return {StatusCode::ResourceExhausted, "not enough free disk space for this upload"};
        nextDiskCheck_ = bytes_ + kDiskCheckInterval;
    }
    hash_.update(data, size);
    out_.write(static_cast<const char*>(data), std::streamsize(size));
    if (!out_) return internalError(file_.string() + ": write failed");
    return {};
}

ServiceResult<v1::Scene> SceneUpload::finish(bool async) {
    if (finished_) return ServiceStatus{StatusCode::FailedPrecondition, "upload already finished"};
    out_.close();
    if (!out_) return internalError(file_.string() + ": write failed");
    if (bytes_ == 0) return invalidArgument("data", "the upload is empty");
    const std::string digest = hash_.finishHex();
    auto scene = async ? service_.queueImport(name_, file_, digest, bytes_)
                       : service_.storeUpload(name_, file_, digest, bytes_);
    std::error_code error;
    fs::remove(file_, error);
    finished_ = true;
    return scene;
}

ServiceStatus Service::checkUploadStart(const std::string& name, uint64_t expectedBytes, uint64_t maxBytes) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!accepting_) return ServiceStatus{StatusCode::Unavailable, "the server is shutting down"};
    }
    if (name.empty()) return invalidArgument("name", "required (the file name, e.g. bunny.ply)");
    if (name.size() > kMaxNameLength || name.find('/') != std::string::npos ||
        name.find('\0') != std::string::npos)
        return invalidArgument(
            "name", "a file name without '/', at most " + std::to_string(kMaxNameLength) + " characters");
    if (expectedBytes > maxBytes)
        return ServiceStatus{StatusCode::ResourceExhausted, name + ": upload of " + std::to_string(expectedBytes) +
                                                                " bytes exceeds the server's limit of " +
                                                                std::to_string(maxBytes)};
    if (expectedBytes + options_.diskReserveBytes > objects_->availableBytes())
        return ServiceStatus{StatusCode::ResourceExhausted, "not enough free disk space for this upload"};
    return {};
}

ServiceResult<std::unique_ptr<SceneUpload>> Service::beginUpload(const std::string& name,
                                                                 uint64_t expectedBytes) {
    if (ServiceStatus s = checkUploadStart(name, expectedBytes, options_.maxUploadBytes); !s) return s;
    const fs::path file = objects_->scratchDir() / ("upload-" + randomHex(16) + ".part");
    auto upload = std::unique_ptr<SceneUpload>(new SceneUpload(*this, name, file, options_.maxUploadBytes));
    if (!upload->out_) return internalError(file.string() + ": cannot create");
    return upload;
}

ServiceResult<v1::Scene> Service::storeUpload(const std::string& name, const fs::path& file,
                                              const std::string& digest, uint64_t bytes,
                                              const ImportProgress& progress) {
    std::lock_guard<std::mutex> importLock(importMutex_);
    auto known = stores_.scenes->getScene(digest);
    if (!known) return internalError(known.message());
    if (*known) return **known;
    return importUpload(name, file, digest, bytes, progress);
}

ServiceResult<v1::Scene> Service::importUpload(const std::string& name, const fs::path& file,
                                               const std::string& digest, uint64_t bytes,
                                               const ImportProgress& progress) {
    v1::Scene scene;
    scene.set_id(digest);
    scene.set_name(name);
    scene.set_format(detectFormat(name, file));
    scene.set_upload_bytes(bytes);
    if (scene.format().empty())
        return invalidArgument("name",
                               "'" + name + "': unknown format; expected .obj, .ply, .gltf, .glb, .zip, .vast or " +
                                   assimpFormatList());
    const fs::path package = objects_->scratchDir() / (digest + "-" + randomHex(8) + ".vast");
    std::error_code error;
    std::vector<std::string> warnings;
    if (scene.format() == "vast") {
        fs::rename(file, package, error);
        if (error) return internalError(package.string() + ": " + error.message());
    } else if (scene.format() == "zip") {
        if (ServiceStatus imported = importZip(name, file, package, warnings, progress); !imported) return imported;
    } else {
        // Importers pick the format by extension: give the scratch file the right one.
        const fs::path mesh = fs::path(file).replace_extension("." + scene.format());
        fs::rename(file, mesh, error);
        if (error) return internalError(mesh.string() + ": " + error.message());
        ServiceStatus imported =
            importMeshFile(mesh, package, {{mesh.string(), name}, {mesh.filename().string(), name}}, warnings, progress);
        fs::remove(mesh, error);
        if (!imported) return imported;
    }
    auto reader = PackageReader::open(package.string());
    std::vector<std::string> damage = reader ? (*reader)->verify() : std::vector<std::string>{};
    if (!reader || !damage.empty()) {
        fs::remove(package, error);
        const std::string why = !reader ? reader.message() : damage.front();
        return invalidArgument("data",
                               "not a valid scene package: " + renamePath(why, package.string(), name));
    }
    scene.set_triangles((*reader)->info().triangleCount);
    scene.set_chunks((*reader)->info().chunks.size());
    for (const std::string& warning : warnings) scene.add_import_warnings(warning);
    addCameras(scene, (*reader)->info().cameras);
    scene.set_package_bytes((*reader)->info().fileBytes);
    reader->reset();
    *scene.mutable_create_time() = nowTimestamp();
    if (Status stored = objects_->put(sceneKey(digest), package); !stored)
        return internalError(stored.message());
    auto inserted = stores_.scenes->insertScene(scene);
    if (!inserted) return internalError(inserted.message());
    ++metrics_.scenesUploaded;
    return *inserted;
}

ServiceResult<v1::FindMissingResponse> Service::findMissing(const v1::FindMissingRequest& request) {
    v1::FindMissingResponse response;
    for (int i = 0; i < request.digests_size(); ++i) {
        const std::string& digest = request.digests(i);
        if (!isSha256Hex(digest))
            return invalidArgument("digests[" + std::to_string(i) + "]", "expected 64 lowercase hex digits");
        auto scene = stores_.scenes->getScene(digest);
        if (!scene) return internalError(scene.message());
        if (!*scene) response.add_missing(digest);
    }
    return response;
}

ServiceResult<v1::Scene> Service::getScene(const v1::GetSceneRequest& request) {
    if (!isSha256Hex(request.id())) return invalidArgument("id", "expected 64 lowercase hex digits");
    auto scene = stores_.scenes->getScene(request.id());
    if (!scene) return internalError(scene.message());
    if (!*scene) {
        std::lock_guard<std::mutex> lock(mutex_);
        return notFound("no scene " + request.id() + importNoteLocked(request.id()));
    }
    return **scene;
}

ServiceResult<v1::ListScenesResponse> Service::listScenes(const v1::ListScenesRequest& request) {
    auto size = pageSize(request.page_size());
    if (!size) return size.status();
    auto after = parsePageToken(request.page_token());
    if (!after) return after.status();
    auto page = stores_.scenes->listScenes(*after, *size);
    if (!page) return internalError(page.message());
    v1::ListScenesResponse response;
    for (auto& scene : page->scenes) *response.add_scenes() = std::move(scene);
    if (page->more) response.set_next_page_token(std::to_string(page->last));
    return response;
}

ServiceResult<v1::DeleteSceneResponse> Service::deleteScene(const v1::DeleteSceneRequest& request) {
    if (!isSha256Hex(request.id())) return invalidArgument("id", "expected 64 lowercase hex digits");
    std::lock_guard<std::mutex> importLock(importMutex_);
    std::lock_guard<std::mutex> lock(mutex_);
    auto scene = stores_.scenes->getScene(request.id());
    if (!scene) return internalError(scene.message());
    if (!*scene) return notFound("no scene " + request.id());
    auto inUse = stores_.jobs->sceneInUse(request.id());
    if (!inUse) return internalError(inUse.message());
    if (*inUse)
        return ServiceStatus{
            StatusCode::FailedPrecondition,
            "scene " + request.id() + " is used by a JOB_STATE_QUEUED or JOB_STATE_RUNNING job"};
    if (Status removed = stores_.scenes->deleteScene(request.id()); !removed)
        return internalError(removed.message());
    if (Status removed = objects_->remove(sceneKey(request.id())); !removed)
        return internalError(removed.message());
    return v1::DeleteSceneResponse();
}

}  // namespace vastray::server
