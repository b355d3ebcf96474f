#include "package/ChunkCodec.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <mutex>
#include <string>

#include "package/ByteIo.h"

namespace vastray {
namespace {

// Draco's integer coder sizes a symbol histogram by the largest value it sees (the first
// vertex of each component is coded against zero), so its cost grows with the coordinate
// range. Grid coordinates are therefore made chunk-relative, and beyond kPredictedBits the
// low bits travel in a second attribute: the high part keeps edgebreaker's parallelogram
// prediction, the low part is near-random at such precision anyway.
constexpr uint32_t kPredictedBits = 18;
// Codec prefix before the Draco stream: chunk minimum (3 × int32), low-bit count (uint32).
constexpr size_t kPrefixBytes = 16;

void addAttribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, draco::DataType dataType,
                  const std::vector<int32_t>& words) {
    const uint32_t count = uint32_t(words.size() / 3);
    draco::GeometryAttribute attribute;
    attribute.Init(type, nullptr, 3, dataType, false, 12, 0);
    draco::PointAttribute* added = mesh.attribute(mesh.AddAttribute(attribute, true, count));
    for (uint32_t v = 0; v < count; ++v) added->SetAttributeValue(draco::AttributeValueIndex(v), &words[3 * size_t(v)]);
}

// A per-vertex word as Draco components: a normal as two 16-bit words (its octahedral code), a
// colour as four bytes, so that Draco's predictors see each component on its own.
void addPackedAttribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, const std::vector<uint32_t>& packed) {
    const bool normal = type == draco::GeometryAttribute::NORMAL;
    draco::GeometryAttribute attribute;
    attribute.Init(type, nullptr, normal ? 2 : 4, normal ? draco::DT_INT16 : draco::DT_UINT8, false, 4, 0);
    draco::PointAttribute* added = mesh.attribute(mesh.AddAttribute(attribute, true, uint32_t(packed.size())));
    for (uint32_t v = 0; v < packed.size(); ++v) added->SetAttributeValue(draco::AttributeValueIndex(v), &packed[v]);
}

bool readPackedAttribute(const draco::Mesh& mesh, draco::GeometryAttribute::Type type, std::vector<uint32_t>& packed) {
    const bool normal = type == draco::GeometryAttribute::NORMAL;
    const draco::PointAttribute* attribute = mesh.GetNamedAttribute(type);
    if (!attribute || attribute->num_components() != (normal ? 2 : 4) ||
        attribute->data_type() != (normal ? draco::DT_INT16 : draco::DT_UINT8))
        return false;
    packed.resize(mesh.num_points());
    for (uint32_t p = 0; p < mesh.num_points(); ++p)
        std::memcpy(&packed[p], attribute->GetAddress(attribute->mapped_index(draco::PointIndex(p))), 4);
    return true;
}

// Texture coordinates as Draco's TEX_COORD, two f32 components and no quantization: Draco then
// stores the values raw (no prediction for floats it may not quantize), so they decode bit for
// bit, each point (vertex) with its own pair, seams included.
void addUvAttribute(draco::Mesh& mesh, const std::vector<std::array<float, 2>>& uvs) {
    draco::GeometryAttribute attribute;
    attribute.Init(draco::GeometryAttribute::TEX_COORD, nullptr, 2, draco::DT_FLOAT32, false, 8, 0);
    draco::PointAttribute* added = mesh.attribute(mesh.AddAttribute(attribute, true, uint32_t(uvs.size())));
    for (uint32_t v = 0; v < uvs.size(); ++v) added->SetAttributeValue(draco::AttributeValueIndex(v), uvs[v].data());
}

bool readUvAttribute(const draco::Mesh& mesh, std::vector<std::array<float, 2>>& uvs) {
    const draco::PointAttribute* attribute = mesh.GetNamedAttribute(draco::GeometryAttribute::TEX_COORD);
    if (!attribute || attribute->num_components() != 2 || attribute->data_type() != draco::DT_FLOAT32) return false;
    uvs.resize(mesh.num_points());
    for (uint32_t p = 0; p < mesh.num_points(); ++p)
        std::memcpy(uvs[p].data(), attribute->GetAddress(attribute->mapped_index(draco::PointIndex(p))), 8);
    return true;
}

bool readAttribute(const draco::Mesh& mesh, const draco::PointAttribute* attribute, draco::DataType dataType,
                   std::vector<int32_t>& words) {
    if (!attribute || attribute->num_components() != 3 || attribute->data_type() != dataType) return false;
    words.resize(size_t(mesh.num_points()) * 3);
    for (uint32_t p = 0; p < mesh.num_points(); ++p)
        std::memcpy(&words[3 * size_t(p)], attribute->GetAddress(attribute->mapped_index(draco::PointIndex(p))), 12);
    return true;
}

// Per-axis minimum of the chunk's words (zeros for an empty chunk): the origin both codecs
// store the words relative to.
std::array<int32_t, 3> chunkMinimum(const std::vector<int32_t>& words) {
    std::array<int32_t, 3> minimum{0, 0, 0};
    if (words.empty()) return minimum;
    for (int axis = 0; axis < 3; ++axis) {
        minimum[axis] = words[axis];
        for (size_t i = axis; i < words.size(); i += 3) minimum[axis] = std::min(minimum[axis], words[i]);
    }
    return minimum;
}

Result<std::vector<uint8_t>> encodeDraco(const ChunkGeometry& geometry, bool lossless, int speed) {
    const size_t vertexCount = geometry.vertexWords.size() / 3;
    std::array<int32_t, 3> minimum{0, 0, 0};
    uint32_t lowBits = 0;
    std::vector<int32_t> high = geometry.vertexWords, low;
    if (!lossless && vertexCount > 0) {
        minimum = chunkMinimum(geometry.vertexWords);
        uint32_t largest = 0;
        for (size_t i = 0; i < high.size(); ++i) largest = std::max(largest, uint32_t(high[i] -= minimum[i % 3]));
        const uint32_t width = uint32_t(std::bit_width(largest));
        lowBits = width > kPredictedBits ? width - kPredictedBits : 0;
        if (lowBits) {
            low.resize(high.size());
            for (size_t i = 0; i < high.size(); ++i) {
                low[i] = high[i] & int32_t((1u << lowBits) - 1);
                high[i] >>= lowBits;
            }
        }
    }
    draco::Mesh mesh;
    mesh.set_num_points(uint32_t(vertexCount));
    addAttribute(mesh, draco::GeometryAttribute::POSITION, lossless ? draco::DT_FLOAT32 : draco::DT_INT32, high);
    if (lowBits) addAttribute(mesh, draco::GeometryAttribute::GENERIC, draco::DT_INT32, low);
    if (!geometry.normals.empty()) addPackedAttribute(mesh, draco::GeometryAttribute::NORMAL, geometry.normals);
    if (!geometry.colors.empty()) addPackedAttribute(mesh, draco::GeometryAttribute::COLOR, geometry.colors);
    if (!geometry.uvs.empty()) addUvAttribute(mesh, geometry.uvs);
    const uint32_t faceCount = uint32_t(geometry.indices.size() / 3);
    mesh.SetNumFaces(faceCount);
    for (uint32_t f = 0; f < faceCount; ++f) {
        const uint32_t* i = &geometry.indices[3 * size_t(f)];
        mesh.SetFace(draco::FaceIndex(f), {draco::PointIndex(i[0]), draco::PointIndex(i[1]), draco::PointIndex(i[2])});
    }
    draco::Encoder encoder;
    encoder.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
    encoder.SetSpeedOptions(speed, speed);
    draco::EncoderBuffer buffer;
    const draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
    if (!status.ok()) return Status::error(std::string("Draco encode failed: ") + status.error_msg());
    ByteWriter out;
    for (int32_t m : minimum) out.put(m);
    out.put(lowBits);
    out.putBytes(buffer.data(), buffer.size());
    return std::move(out.bytes());
}

Result<ChunkGeometry> decodeDraco(const uint8_t* data, size_t size, bool lossless, GeometryAttributes attributes) {
    ByteReader in(data, size);
    int32_t minimum[3];
    uint32_t lowBits = 0;
    for (int32_t& m : minimum) in.get(m);
    in.get(lowBits);
    if (!in.ok() || lowBits > 31) return Status::error("bad geometry prefix");
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data + kPrefixBytes), size - kPrefixBytes);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) return Status::error(std::string("Draco decode failed: ") + decoded.status().error_msg());
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    ChunkGeometry geometry;
    if (!readAttribute(*mesh, mesh->GetNamedAttribute(draco::GeometryAttribute::POSITION),
                       lossless ? draco::DT_FLOAT32 : draco::DT_INT32, geometry.vertexWords))
        return Status::error("Draco stream has no 3-component position of the expected type");
    if (lowBits) {
        std::vector<int32_t> low;
        if (!readAttribute(*mesh, mesh->GetNamedAttribute(draco::GeometryAttribute::GENERIC), draco::DT_INT32, low))
            return Status::error("Draco stream lacks the low position bits");
        if (low.size() != geometry.vertexWords.size())
            return Status::error("Draco stream's low position bits are not one per coordinate");
        for (size_t i = 0; i < low.size(); ++i)
            geometry.vertexWords[i] = int32_t((uint32_t(geometry.vertexWords[i]) << lowBits) | uint32_t(low[i]));
    }
    if (attributes.normals && !readPackedAttribute(*mesh, draco::GeometryAttribute::NORMAL, geometry.normals))
        return Status::error("Draco stream lacks the chunk's normals (2 x int16 per vertex)");
    if (attributes.colors && !readPackedAttribute(*mesh, draco::GeometryAttribute::COLOR, geometry.colors))
        return Status::error("Draco stream lacks the chunk's colours (4 x uint8 per vertex)");
    if (attributes.uvs && !readUvAttribute(*mesh, geometry.uvs))
        return Status::error("Draco stream lacks the chunk's texture coordinates (2 x float32 per vertex)");
    // Modular 32-bit addition, as the meshopt stream's: a forged minimum wraps (the positions
    // are then checked against the grid like any others) instead of overflowing a signed int.
    if (!lossless)
        for (size_t i = 0; i < geometry.vertexWords.size(); ++i)
            geometry.vertexWords[i] = int32_t(uint32_t(geometry.vertexWords[i]) + uint32_t(minimum[i % 3]));
    geometry.indices.resize(size_t(mesh->num_faces()) * 3);
    for (uint32_t f = 0; f < mesh->num_faces(); ++f) {
        const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(f));
        for (int c = 0; c < 3; ++c) geometry.indices[3 * size_t(f) + c] = face[c].value();
    }
    return geometry;
}

// Meshopt stream: chunk minimum (3 x int32), vertex count, index count, vertex stride, index
// stream bytes (4 x uint32), then meshoptimizer's index stream and vertex stream. Words are
// stored relative to the chunk minimum in modular 32-bit arithmetic (so float bit patterns
// work too): 4 x uint16 (w = 0; the vertex codec wants a stride that is a multiple of 4) when
// every offset fits 16 bits, else 3 x uint32. Between the index stream and the position stream
// (which ends the blob), for each attribute the chunk has (normals, then colours): its stream's
// bytes (uint32) and meshoptimizer's vertex stream of one word per vertex, in position order;
// then, with texture coordinates, their stream's bytes and a stream of two f32 per vertex.
Result<std::vector<uint8_t>> encodeMeshopt(const ChunkGeometry& geometry) {
    // Index codec version 1 (smaller); set once, before any thread encodes (a global in meshopt).
    static std::once_flag version;
    std::call_once(version, [] { meshopt_encodeIndexVersion(1); });
    const size_t vertexCount = geometry.vertexWords.size() / 3, indexCount = geometry.indices.size();
    const std::array<int32_t, 3> minimum = chunkMinimum(geometry.vertexWords);
    auto offset = [&](size_t i) { return uint32_t(geometry.vertexWords[i]) - uint32_t(minimum[i % 3]); };
    uint32_t largest = 0;
    for (size_t i = 0; i < geometry.vertexWords.size(); ++i) largest = std::max(largest, offset(i));
    const uint32_t stride = std::bit_width(largest) <= 16 ? 8 : 12;
    std::vector<uint8_t> vertices(vertexCount * stride, 0);
    for (size_t v = 0; v < vertexCount; ++v)
        for (size_t a = 0; a < 3; ++a) {
            const uint32_t r = offset(3 * v + a);
            if (stride == 8) {
                const uint16_t r16 = uint16_t(r);
                std::memcpy(&vertices[v * 8 + a * 2], &r16, 2);
            } else {
                std::memcpy(&vertices[v * 12 + a * 4], &r, 4);
            }
        }
    std::vector<uint32_t> indices(indexCount);
    meshopt_optimizeVertexCache(indices.data(), geometry.indices.data(), indexCount, vertexCount);
    std::vector<uint32_t> remap(vertexCount);
    const size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indexCount, vertexCount);
    meshopt_remapIndexBuffer(indices.data(), indices.data(), indexCount, remap.data());
    std::vector<uint8_t> fetched(used * stride);
    meshopt_remapVertexBuffer(fetched.data(), vertices.data(), vertexCount, stride, remap.data());
    std::vector<uint8_t> indexStream(meshopt_encodeIndexBufferBound(indexCount, used));
    indexStream.resize(meshopt_encodeIndexBuffer(indexStream.data(), indexStream.size(), indices.data(), indexCount));
    std::vector<uint8_t> vertexStream(meshopt_encodeVertexBufferBound(used, stride));
    vertexStream.resize(meshopt_encodeVertexBuffer(vertexStream.data(), vertexStream.size(), fetched.data(), used, stride));
    if (indexStream.empty() || vertexStream.empty()) return Status::error("meshopt encode returned no bytes");
    ByteWriter out;
    for (int32_t m : minimum) out.put(m);
    for (uint32_t field : {uint32_t(used), uint32_t(indexCount), stride, uint32_t(indexStream.size())}) out.put(field);
    out.putBytes(indexStream.data(), indexStream.size());
    for (const std::vector<uint32_t>* words : {&geometry.normals, &geometry.colors}) {
        if (words->empty()) continue;
        std::vector<uint32_t> ordered(used);
        meshopt_remapVertexBuffer(ordered.data(), words->data(), vertexCount, 4, remap.data());
        std::vector<uint8_t> stream(meshopt_encodeVertexBufferBound(used, 4));
        stream.resize(meshopt_encodeVertexBuffer(stream.data(), stream.size(), ordered.data(), used, 4));
        if (stream.empty()) return Status::error("meshopt encode returned no bytes for an attribute");
        out.put(uint32_t(stream.size()));
        out.putBytes(stream.data(), stream.size());
    }
    if (!geometry.uvs.empty()) {
        std::vector<std::array<float, 2>> ordered(used);
        meshopt_remapVertexBuffer(ordered.data(), geometry.uvs.data(), vertexCount, 8, remap.data());
        std::vector<uint8_t> stream(meshopt_encodeVertexBufferBound(used, 8));
        stream.resize(meshopt_encodeVertexBuffer(stream.data(), stream.size(), ordered.data(), used, 8));
        if (stream.empty()) return Status::error("meshopt encode returned no bytes for the texture coordinates");
        out.put(uint32_t(stream.size()));
        out.putBytes(stream.data(), stream.size());
    }
    out.putBytes(vertexStream.data(), vertexStream.size());
    return std::move(out.bytes());
}

Result<ChunkGeometry> decodeMeshopt(const uint8_t* data, size_t size, GeometryAttributes attributes) {
    ByteReader in(data, size);
    int32_t minimum[3];
    uint32_t vertexCount = 0, indexCount = 0, stride = 0, indexBytes = 0;
    for (int32_t& m : minimum) in.get(m);
    for (uint32_t* field : {&vertexCount, &indexCount, &stride, &indexBytes}) in.get(*field);
    // The index codec spends at least one byte per triangle plus 17 (meshoptimizer's
    // decoder checks the same), and every vertex is used: this bounds both counts by the
    // stream's size before anything is allocated.
    if (!in.ok() || (stride != 8 && stride != 12) || indexCount % 3 != 0 || indexBytes > in.remaining() ||
        uint64_t(indexCount) / 3 + 17 > indexBytes || vertexCount > indexCount)
        return Status::error("bad meshopt prefix");
    ChunkGeometry geometry;
    geometry.indices.resize(indexCount);
    if (meshopt_decodeIndexBuffer(geometry.indices.data(), indexCount, 4, in.current(), indexBytes) != 0)
        return Status::error("meshopt index stream is corrupt");
    in.skip(indexBytes);
    for (auto [wanted, words] : {std::pair{attributes.normals, &geometry.normals}, {attributes.colors, &geometry.colors}}) {
        if (!wanted) continue;
        uint32_t bytes = 0;
        in.get(bytes);
        if (!in.ok() || bytes > in.remaining()) return Status::error("meshopt attribute stream overruns the chunk");
        words->resize(vertexCount);
        if (meshopt_decodeVertexBuffer(words->data(), vertexCount, 4, in.current(), bytes) != 0)
            return Status::error("meshopt attribute stream is corrupt");
        in.skip(bytes);
    }
    if (attributes.uvs) {
        uint32_t bytes = 0;
        in.get(bytes);
        if (!in.ok() || bytes > in.remaining()) return Status::error("meshopt texture coordinate stream overruns the chunk");
        geometry.uvs.resize(vertexCount);
        if (meshopt_decodeVertexBuffer(geometry.uvs.data(), vertexCount, 8, in.current(), bytes) != 0)
            return Status::error("meshopt texture coordinate stream is corrupt");
        in.skip(bytes);
    }
    std::vector<uint8_t> vertices(size_t(vertexCount) * stride);
    if (meshopt_decodeVertexBuffer(vertices.data(), vertexCount, stride, in.current(), in.remaining()) != 0)
        return Status::error("meshopt vertex stream is corrupt");
    geometry.vertexWords.resize(size_t(vertexCount) * 3);
    for (size_t v = 0; v < vertexCount; ++v)
        for (size_t a = 0; a < 3; ++a) {
            uint32_t r = 0;
            if (stride == 8) {
                uint16_t r16;
                std::memcpy(&r16, &vertices[v * 8 + a * 2], 2);
                r = r16;
            } else {
                std::memcpy(&r, &vertices[v * 12 + a * 4], 4);
            }
            geometry.vertexWords[3 * v + a] = int32_t(r + uint32_t(minimum[a]));
        }
    return geometry;
}

}  // namespace

Result<std::vector<uint8_t>> encodeChunkGeometry(const ChunkGeometry& geometry, bool lossless, GeometryCodec codec,
                                                 int dracoSpeed) {
    return codec == GeometryCodec::Meshopt ? encodeMeshopt(geometry) : encodeDraco(geometry, lossless, dracoSpeed);
}

Result<ChunkGeometry> decodeChunkGeometry(const uint8_t* data, size_t size, bool lossless, GeometryCodec codec,
                                          GeometryAttributes attributes) {
    if (codec == GeometryCodec::Meshopt) return decodeMeshopt(data, size, attributes);
    return decodeDraco(data, size, lossless, attributes);
}

const char* geometryCodecName(GeometryCodec codec) { return codec == GeometryCodec::Meshopt ? "meshopt" : "draco"; }

Result<GeometryCodec> parseGeometryCodec(const std::string& name) {
    if (name == "draco") return GeometryCodec::Draco;
    if (name == "meshopt") return GeometryCodec::Meshopt;
    return Status::error("unknown codec '" + name + "' (expected draco or meshopt)");
}

}  // namespace vastray
