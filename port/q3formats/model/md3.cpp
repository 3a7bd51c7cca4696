#include "port/q3formats/model/md3.h"

#include <cmath>

#include "port/q3formats/common/byte_reader.h"
#include "port/q3formats/common/tokenizer.h"

namespace q3 {
namespace {

// File layout (little-endian), sizes from the format.
constexpr size_t kHeaderSize = 108;        // ident, version, name[64], flags, 4 counts, 4 offsets
constexpr size_t kFrameSize = 56;          // mins, maxs, origin, radius, name[16]
constexpr size_t kTagSize = 112;           // name[64], origin, axis[3]
constexpr size_t kSurfaceHeaderSize = 108; // ident, name[64], flags, 4 counts, 5 offsets (the last is ofsEnd)
constexpr size_t kShaderSize = 68;         // name[64], index
constexpr size_t kTriangleSize = 12;
constexpr size_t kTexCoordSize = 8;
constexpr size_t kVertexSize = 8;          // short xyz[3], short normal
constexpr double kPi = 3.14159265358979323846;

Md3Vec3 readVec3(const ByteReader& r, size_t offset, const char* field) {
  Md3Vec3 v;
  for (int i = 0; i < 3; ++i) {
    v[i] = r.read<float>(offset + 4 * i, field);
    if (!std::isfinite(v[i])) r.fail(field, "not a finite number");
  }
  return v;
}

int32_t readCount(const ByteReader& r, size_t offset, const char* field, int max) {
  const int32_t n = r.read<int32_t>(offset, field);
  if (n < 0 || n > max)
    r.fail(field, std::to_string(n) + " outside 0.." + std::to_string(max));
  return n;
}

size_t readOffset(const ByteReader& r, size_t offset, const char* field) {
  const int32_t o = r.read<int32_t>(offset, field);
  if (o < 0) r.fail(field, "negative offset " + std::to_string(o));
  return static_cast<size_t>(o);
}

Md3Vec3 normalized(Md3Vec3 v) {
  const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (len > 0)
    for (float& c : v) c /= len;
  return v;
}

Md3Surface parseSurface(const ByteReader& file, size_t start, size_t numFrames, int index) {
  const std::string where = "surface " + std::to_string(index);
  file.require(start, 1, kSurfaceHeaderSize, where.c_str());
  // Every offset inside a surface is relative to its start; the surface must fit in the file.
  const size_t ofsEnd = readOffset(file, start + 104, (where + " ofsEnd").c_str());
  file.require(start, ofsEnd, 1, (where + " extent").c_str());
  if (ofsEnd < kSurfaceHeaderSize) file.fail((where + " ofsEnd").c_str(), "smaller than the surface header");
  const ByteReader r(file.bytes(start, ofsEnd, where.c_str()), file.file() + " " + where);

  if (r.fixedString(0, 4, "ident") != "IDP3") r.fail("ident", "not IDP3");
  Md3Surface s;
  s.name = r.fixedString(4, 64, "name");
  s.flags = r.read<int32_t>(68, "flags");
  const int32_t frames = readCount(r, 72, "numFrames", Md3Limits::maxFrames);
  if (static_cast<size_t>(frames) != numFrames)
    r.fail("numFrames", std::to_string(frames) + " differs from the model's " + std::to_string(numFrames));
  const int32_t numShaders = readCount(r, 76, "numShaders", Md3Limits::maxShaders);
  s.numVerts = readCount(r, 80, "numVerts", Md3Limits::maxVerts);
  const int32_t numTriangles = readCount(r, 84, "numTriangles", Md3Limits::maxTriangles);
  const size_t ofsTriangles = readOffset(r, 88, "ofsTriangles");
  const size_t ofsShaders = readOffset(r, 92, "ofsShaders");
  const size_t ofsSt = readOffset(r, 96, "ofsSt");
  const size_t ofsXyz = readOffset(r, 100, "ofsXyzNormals");

  r.require(ofsShaders, static_cast<size_t>(numShaders), kShaderSize, "shaders");
  for (int i = 0; i < numShaders; ++i) {
    const size_t o = ofsShaders + static_cast<size_t>(i) * kShaderSize;
    s.shaders.push_back({r.fixedString(o, 64, "shader name"), r.read<int32_t>(o + 64, "shader index")});
  }

  r.require(ofsTriangles, static_cast<size_t>(numTriangles), kTriangleSize, "triangles");
  s.triangles.resize(static_cast<size_t>(numTriangles));
  for (int i = 0; i < numTriangles; ++i)
    for (int k = 0; k < 3; ++k) {
      const int32_t v = r.read<int32_t>(ofsTriangles + static_cast<size_t>(i) * kTriangleSize + 4 * k, "triangle index");
      if (v < 0 || v >= s.numVerts)
        r.fail("triangles", "triangle " + std::to_string(i) + " index " + std::to_string(v) + " outside 0.." +
                                std::to_string(s.numVerts - 1));
      s.triangles[i][k] = static_cast<uint32_t>(v);
    }

  r.require(ofsSt, static_cast<size_t>(s.numVerts), kTexCoordSize, "texture coordinates");
  s.texCoords.resize(static_cast<size_t>(s.numVerts));
  for (int i = 0; i < s.numVerts; ++i)
    for (int k = 0; k < 2; ++k) {
      const float f = r.read<float>(ofsSt + static_cast<size_t>(i) * kTexCoordSize + 4 * k, "st");
      if (!std::isfinite(f)) r.fail("st", "not a finite number");
      s.texCoords[i][k] = f;
    }

  const size_t count = numFrames * static_cast<size_t>(s.numVerts);
  r.require(ofsXyz, count, kVertexSize, "xyz normals");
  s.positions.resize(count);
  s.normals.resize(count);
  for (size_t i = 0; i < count; ++i) {
    const size_t o = ofsXyz + i * kVertexSize;
    for (int k = 0; k < 3; ++k) s.positions[i][k] = r.read<int16_t>(o + 2 * k, "xyz") * Md3Limits::xyzScale;
    s.normals[i] = decodeMd3Normal(r.read<uint16_t>(o + 6, "normal"));
  }
  return s;
}

}  // namespace

Md3Vec3 decodeMd3Normal(uint16_t packed) {
  const double lat = ((packed >> 8) & 0xFF) * (2 * kPi / 256.0);
  const double lng = (packed & 0xFF) * (2 * kPi / 256.0);
  return {static_cast<float>(std::cos(lat) * std::sin(lng)), static_cast<float>(std::sin(lat) * std::sin(lng)),
          static_cast<float>(std::cos(lng))};
}

Md3Model parseMd3(std::span<const std::byte> bytes, const std::string& name) {
  const ByteReader r(bytes, name);
  r.require(0, 1, kHeaderSize, "header");
  if (r.fixedString(0, 4, "ident") != "IDP3") r.fail("ident", "not an MD3 file (expected IDP3)");
  const int32_t version = r.read<int32_t>(4, "version");
  if (version != Md3Limits::version) r.fail("version", std::to_string(version) + ", expected 15");
  Md3Model m;
  m.name = r.fixedString(8, 64, "name");
  m.flags = r.read<int32_t>(72, "flags");
  const int32_t numFrames = readCount(r, 76, "numFrames", Md3Limits::maxFrames);
  m.numTags = readCount(r, 80, "numTags", Md3Limits::maxTags);
  const int32_t numSurfaces = readCount(r, 84, "numSurfaces", Md3Limits::maxSurfaces);
  readCount(r, 88, "numSkins", Md3Limits::maxShaders);  // unused by the format's readers
  const size_t ofsFrames = readOffset(r, 92, "ofsFrames");
  const size_t ofsTags = readOffset(r, 96, "ofsTags");
  const size_t ofsSurfaces = readOffset(r, 100, "ofsSurfaces");
  const size_t ofsEnd = readOffset(r, 104, "ofsEnd");
  if (ofsEnd > r.size()) r.fail("ofsEnd", "beyond the end of the file");
  if (numFrames < 1) r.fail("numFrames", "a model needs at least one frame");

  r.require(ofsFrames, static_cast<size_t>(numFrames), kFrameSize, "frames");
  for (int i = 0; i < numFrames; ++i) {
    const size_t o = ofsFrames + static_cast<size_t>(i) * kFrameSize;
    Md3Frame f;
    f.mins = readVec3(r, o, "frame bounds");
    f.maxs = readVec3(r, o + 12, "frame bounds");
    f.localOrigin = readVec3(r, o + 24, "frame origin");
    f.radius = r.read<float>(o + 36, "frame radius");
    if (!std::isfinite(f.radius)) r.fail("frame radius", "not a finite number");
    f.name = r.fixedString(o + 40, 16, "frame name");
    m.frames.push_back(std::move(f));
  }

  const size_t numTagRecords = static_cast<size_t>(numFrames) * static_cast<size_t>(m.numTags);
  r.require(ofsTags, numTagRecords, kTagSize, "tags");
  m.tags.resize(numTagRecords);
  for (size_t i = 0; i < numTagRecords; ++i) {
    const size_t o = ofsTags + i * kTagSize;
    Md3Tag& t = m.tags[i];
    t.name = r.fixedString(o, 64, "tag name");
    t.origin = readVec3(r, o + 64, "tag origin");
    for (int a = 0; a < 3; ++a) t.axis[a] = readVec3(r, o + 76 + 12 * a, "tag axis");
  }

  size_t offset = ofsSurfaces;
  for (int i = 0; i < numSurfaces; ++i) {
    m.surfaces.push_back(parseSurface(r, offset, static_cast<size_t>(numFrames), i));
    offset += static_cast<size_t>(r.read<int32_t>(offset + 104, "surface ofsEnd"));  // checked > 0 above
  }
  return m;
}

void lerpSurface(const Md3Surface& surface, size_t numFrames, int frame, int oldFrame, float backlerp,
                 std::vector<Md3Vec3>& positions, std::vector<Md3Vec3>& normals) {
  const size_t n = static_cast<size_t>(surface.numVerts);
  auto valid = [&](int f) { return f >= 0 && static_cast<size_t>(f) < numFrames ? static_cast<size_t>(f) : 0; };
  size_t a = valid(frame), b = valid(oldFrame);
  if (surface.positions.size() < numFrames * n) a = b = 0;  // inconsistent call: use the first frame
  positions.resize(n);
  normals.resize(n);
  const float front = 1.0f - backlerp;
  for (size_t i = 0; i < n; ++i) {
    const Md3Vec3& p0 = surface.positions[a * n + i];
    const Md3Vec3& p1 = surface.positions[b * n + i];
    const Md3Vec3& n0 = surface.normals[a * n + i];
    const Md3Vec3& n1 = surface.normals[b * n + i];
    for (int k = 0; k < 3; ++k) {
      positions[i][k] = p0[k] * front + p1[k] * backlerp;
      normals[i][k] = n0[k] * front + n1[k] * backlerp;
    }
    normals[i] = normalized(normals[i]);
  }
}

std::optional<Md3Tag> lerpTag(const Md3Model& model, int startFrame, int endFrame, float fraction,
                              std::string_view tagName) {
  if (model.frames.empty() || model.numTags == 0) return std::nullopt;
  const int last = static_cast<int>(model.frames.size()) - 1;
  auto clampFrame = [&](int f) { return static_cast<size_t>(f < 0 ? 0 : f > last ? last : f); };
  const size_t fa = clampFrame(startFrame), fb = clampFrame(endFrame);
  for (int t = 0; t < model.numTags; ++t) {
    const Md3Tag& a = model.tag(fa, static_cast<size_t>(t));
    if (a.name != tagName) continue;  // the engine compares tag names with strcmp
    const Md3Tag& b = model.tag(fb, static_cast<size_t>(t));
    Md3Tag out;
    out.name = a.name;
    const float back = 1.0f - fraction;
    for (int k = 0; k < 3; ++k) out.origin[k] = a.origin[k] * back + b.origin[k] * fraction;
    for (int axis = 0; axis < 3; ++axis) {
      for (int k = 0; k < 3; ++k) out.axis[axis][k] = a.axis[axis][k] * back + b.axis[axis][k] * fraction;
      out.axis[axis] = normalized(out.axis[axis]);
    }
    return out;
  }
  return std::nullopt;
}

std::string md3LodName(std::string_view name, int lod) {
  if (lod <= 0) return std::string(name);
  std::string_view stem = name;
  if (stem.size() >= 4 && equalsIgnoreCase(stem.substr(stem.size() - 4), ".md3")) stem.remove_suffix(4);
  return std::string(stem) + "_" + std::to_string(lod) + ".md3";
}

}  // namespace q3
