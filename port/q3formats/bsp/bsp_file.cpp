// IBSP 46 reader: lump table, typed decoding and cross-reference validation.
#include "port/q3formats/bsp/bsp_file.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/common/byte_reader.h"

namespace q3 {
namespace {

constexpr int32_t kBspVersion = 46;
constexpr size_t kHeaderSize = 8 + 17 * 8;
constexpr size_t kLightGridPointSize = 8;

struct LumpRange {
  size_t offset = 0;
  size_t length = 0;
};

/// Decodes one lump: knows its bytes, its name for messages, and its element count.
class LumpReader {
 public:
  LumpReader(const ByteReader& file, LumpRange range, BspLump lump)
      : file_(file), range_(range), lump_(lump), field_(std::string("lump ") + bspLumpName(lump)) {}

  size_t count() const {
    const size_t elem = kBspLumpElementSize[static_cast<int>(lump_)];
    return elem ? range_.length / elem : range_.length;
  }
  template <class T>
  T read(size_t element, size_t fieldOffset) const {
    const size_t elem = kBspLumpElementSize[static_cast<int>(lump_)];
    return file_.read<T>(range_.offset + element * elem + fieldOffset, field_.c_str());
  }
  glm::vec3 readVec3(size_t element, size_t fieldOffset) const {
    glm::vec3 v{read<float>(element, fieldOffset), read<float>(element, fieldOffset + 4),
                read<float>(element, fieldOffset + 8)};
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      fail(element, "non-finite coordinate");
    return v;
  }
  glm::ivec3 readIVec3(size_t element, size_t fieldOffset) const {
    return {read<int32_t>(element, fieldOffset), read<int32_t>(element, fieldOffset + 4),
            read<int32_t>(element, fieldOffset + 8)};
  }
  std::string readName(size_t element, size_t fieldOffset, size_t capacity) const {
    const size_t elem = kBspLumpElementSize[static_cast<int>(lump_)];
    return file_.fixedString(range_.offset + element * elem + fieldOffset, capacity, field_.c_str());
  }
  std::span<const std::byte> bytes() const {
    return file_.bytes(range_.offset, range_.length, field_.c_str());
  }
  [[noreturn]] void fail(size_t element, const std::string& detail) const {
    file_.fail(field_.c_str(), "element " + std::to_string(element) + ": " + detail);
  }
  /// Throws unless index lies in [lo, count).
  void checkIndex(size_t element, const char* what, int64_t index, int64_t lo, size_t count) const {
    if (index < lo || index >= static_cast<int64_t>(count))
      fail(element, std::string(what) + " " + std::to_string(index) + " outside [" +
                        std::to_string(lo) + ", " + std::to_string(count) + ")");
  }
  /// Throws unless [first, first + n) lies inside [0, count).
  void checkRange(size_t element, const char* what, int64_t first, int64_t n, size_t count) const {
    if (first < 0 || n < 0 || first + n > static_cast<int64_t>(count))
      fail(element, std::string(what) + " range [" + std::to_string(first) + ", +" +
                        std::to_string(n) + ") outside [0, " + std::to_string(count) + ")");
  }

 private:
  const ByteReader& file_;
  LumpRange range_;
  BspLump lump_;
  std::string field_;
};

std::array<LumpRange, 17> readLumpTable(const ByteReader& r) {
  r.require(0, 1, kHeaderSize, "header");
  const auto magic = r.fixedString(0, 4, "header magic");
  if (magic != "IBSP") r.fail("header magic", "expected \"IBSP\", found \"" + magic + "\"");
  const auto version = r.read<int32_t>(4, "header version");
  if (version != kBspVersion)
    r.fail("header version", "expected 46, found " + std::to_string(version));
  std::array<LumpRange, 17> lumps{};
  for (int i = 0; i < 17; ++i) {
    const std::string field = std::string("lump table ") + bspLumpName(static_cast<BspLump>(i));
    const auto offset = r.read<int32_t>(8 + i * 8, field.c_str());
    const auto length = r.read<int32_t>(12 + i * 8, field.c_str());
    if (offset < 0 || length < 0)
      r.fail(field.c_str(), "negative offset " + std::to_string(offset) + " or length " +
                                std::to_string(length));
    r.require(static_cast<size_t>(offset), static_cast<size_t>(length), 1, field.c_str());
    const size_t elem = kBspLumpElementSize[i];
    // The engine reads whole lightmap pages and ignores a partial last one (checked below).
    if (elem && length % elem != 0 && static_cast<BspLump>(i) != BspLump::Lightmaps)
      r.fail(field.c_str(), "length " + std::to_string(length) + " is not a multiple of " +
                                std::to_string(elem));
    lumps[i] = {static_cast<size_t>(offset), static_cast<size_t>(length)};
  }
  return lumps;
}

void decodeGeometryLumps(BspFile& bsp, const ByteReader& r, const std::array<LumpRange, 17>& L) {
  auto lump = [&](BspLump which) { return LumpReader(r, L[static_cast<int>(which)], which); };

  const auto shaders = lump(BspLump::Shaders);
  bsp.shaders.resize(shaders.count());
  for (size_t i = 0; i < bsp.shaders.size(); ++i)
    bsp.shaders[i] = {shaders.readName(i, 0, 64), shaders.read<int32_t>(i, 64),
                      shaders.read<int32_t>(i, 68)};

  const auto planes = lump(BspLump::Planes);
  bsp.planes.resize(planes.count());
  for (size_t i = 0; i < bsp.planes.size(); ++i) {
    bsp.planes[i].normal = planes.readVec3(i, 0);
    bsp.planes[i].dist = planes.read<float>(i, 12);
    if (!std::isfinite(bsp.planes[i].dist)) planes.fail(i, "non-finite distance");
  }

  const auto nodes = lump(BspLump::Nodes);
  bsp.nodes.resize(nodes.count());
  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    auto& n = bsp.nodes[i];
    n.plane = nodes.read<int32_t>(i, 0);
    n.children = {nodes.read<int32_t>(i, 4), nodes.read<int32_t>(i, 8)};
    n.mins = nodes.readIVec3(i, 12);
    n.maxs = nodes.readIVec3(i, 24);
  }

  const auto leafs = lump(BspLump::Leafs);
  bsp.leafs.resize(leafs.count());
  for (size_t i = 0; i < bsp.leafs.size(); ++i) {
    auto& f = bsp.leafs[i];
    f.cluster = leafs.read<int32_t>(i, 0);
    f.area = leafs.read<int32_t>(i, 4);
    f.mins = leafs.readIVec3(i, 8);
    f.maxs = leafs.readIVec3(i, 20);
    f.firstLeafSurface = leafs.read<int32_t>(i, 32);
    f.numLeafSurfaces = leafs.read<int32_t>(i, 36);
    f.firstLeafBrush = leafs.read<int32_t>(i, 40);
    f.numLeafBrushes = leafs.read<int32_t>(i, 44);
  }

  const auto readInts = [&](BspLump which, std::vector<int32_t>& out) {
    const auto l = lump(which);
    out.resize(l.count());
    for (size_t i = 0; i < out.size(); ++i) out[i] = l.read<int32_t>(i, 0);
  };
  readInts(BspLump::LeafSurfaces, bsp.leafSurfaces);
  readInts(BspLump::LeafBrushes, bsp.leafBrushes);
  readInts(BspLump::DrawIndexes, bsp.drawIndexes);

  const auto models = lump(BspLump::Models);
  bsp.models.resize(models.count());
  for (size_t i = 0; i < bsp.models.size(); ++i) {
    auto& m = bsp.models[i];
    m.mins = models.readVec3(i, 0);
    m.maxs = models.readVec3(i, 12);
    m.firstSurface = models.read<int32_t>(i, 24);
    m.numSurfaces = models.read<int32_t>(i, 28);
    m.firstBrush = models.read<int32_t>(i, 32);
    m.numBrushes = models.read<int32_t>(i, 36);
  }

  const auto brushes = lump(BspLump::Brushes);
  bsp.brushes.resize(brushes.count());
  for (size_t i = 0; i < bsp.brushes.size(); ++i)
    bsp.brushes[i] = {brushes.read<int32_t>(i, 0), brushes.read<int32_t>(i, 4),
                      brushes.read<int32_t>(i, 8)};

  const auto sides = lump(BspLump::BrushSides);
  bsp.brushSides.resize(sides.count());
  for (size_t i = 0; i < bsp.brushSides.size(); ++i)
    bsp.brushSides[i] = {sides.read<int32_t>(i, 0), sides.read<int32_t>(i, 4)};

  const auto verts = lump(BspLump::DrawVerts);
  bsp.drawVerts.resize(verts.count());
  size_t nonFiniteTexCoords = 0;
  for (size_t i = 0; i < bsp.drawVerts.size(); ++i) {
    auto& v = bsp.drawVerts[i];
    v.position = verts.readVec3(i, 0);
    v.st = {verts.read<float>(i, 12), verts.read<float>(i, 16)};
    v.lightmap = {verts.read<float>(i, 20), verts.read<float>(i, 24)};
    v.normal = verts.readVec3(i, 28);
    v.color = verts.read<std::array<uint8_t, 4>>(i, 40);
    // q3map2 writes NaN lightmap coordinates on vertex-lit surfaces: tolerate, zero, count.
    for (float* f : {&v.st.x, &v.st.y, &v.lightmap.x, &v.lightmap.y})
      if (!std::isfinite(*f)) {
        *f = 0;
        ++nonFiniteTexCoords;
      }
  }
  if (nonFiniteTexCoords)
    bsp.warnings.push_back("draw verts: " + std::to_string(nonFiniteTexCoords) +
                           " non-finite texture/lightmap coordinates replaced by 0");

  const auto fogs = lump(BspLump::Fogs);
  bsp.fogs.resize(fogs.count());
  for (size_t i = 0; i < bsp.fogs.size(); ++i)
    bsp.fogs[i] = {fogs.readName(i, 0, 64), fogs.read<int32_t>(i, 64), fogs.read<int32_t>(i, 68)};

  const auto surfaces = lump(BspLump::Surfaces);
  bsp.surfaces.resize(surfaces.count());
  for (size_t i = 0; i < bsp.surfaces.size(); ++i) {
    auto& s = bsp.surfaces[i];
    s.shader = surfaces.read<int32_t>(i, 0);
    s.fog = surfaces.read<int32_t>(i, 4);
    const auto type = surfaces.read<int32_t>(i, 8);
    if (type < 1 || type > 4) surfaces.fail(i, "unknown surface type " + std::to_string(type));
    s.type = static_cast<SurfaceType>(type);
    s.firstVert = surfaces.read<int32_t>(i, 12);
    s.numVerts = surfaces.read<int32_t>(i, 16);
    s.firstIndex = surfaces.read<int32_t>(i, 20);
    s.numIndexes = surfaces.read<int32_t>(i, 24);
    s.lightmap = surfaces.read<int32_t>(i, 28);
    s.lightmapX = surfaces.read<int32_t>(i, 32);
    s.lightmapY = surfaces.read<int32_t>(i, 36);
    s.lightmapWidth = surfaces.read<int32_t>(i, 40);
    s.lightmapHeight = surfaces.read<int32_t>(i, 44);
    s.lightmapOrigin = surfaces.readVec3(i, 48);
    for (int k = 0; k < 3; ++k) s.lightmapVecs[k] = surfaces.readVec3(i, 60 + 12 * k);
    s.patchWidth = surfaces.read<int32_t>(i, 96);
    s.patchHeight = surfaces.read<int32_t>(i, 100);
  }

  const auto lightmaps = lump(BspLump::Lightmaps).bytes();
  constexpr size_t kPage = kBspLumpElementSize[static_cast<int>(BspLump::Lightmaps)];
  const size_t whole = lightmaps.size() / kPage * kPage;
  if (whole != lightmaps.size())
    bsp.warnings.push_back("lightmaps: " + std::to_string(lightmaps.size() - whole) +
                           " bytes after the last whole 128x128 page ignored");
  bsp.lightmaps.resize(whole);
  if (whole) std::memcpy(bsp.lightmaps.data(), lightmaps.data(), whole);
}

void validateReferences(BspFile& bsp, const ByteReader& r, const std::array<LumpRange, 17>& L) {
  auto lump = [&](BspLump which) { return LumpReader(r, L[static_cast<int>(which)], which); };

  const auto nodes = lump(BspLump::Nodes);
  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    const auto& n = bsp.nodes[i];
    nodes.checkIndex(i, "plane", n.plane, 0, bsp.planes.size());
    for (int32_t child : n.children) {
      if (child >= 0) {
        // Children always follow their parent in q3map's depth-first order; requiring it
        // rules out cycles, so every descent terminates.
        if (static_cast<size_t>(child) <= i)
          nodes.fail(i, "child node " + std::to_string(child) + " does not follow its parent");
        nodes.checkIndex(i, "child node", child, 0, bsp.nodes.size());
      } else {
        nodes.checkIndex(i, "child leaf", -(static_cast<int64_t>(child) + 1), 0, bsp.leafs.size());
      }
    }
  }

  const auto leafs = lump(BspLump::Leafs);
  for (size_t i = 0; i < bsp.leafs.size(); ++i) {
    const auto& f = bsp.leafs[i];
    if (f.cluster < -1) leafs.fail(i, "cluster " + std::to_string(f.cluster) + " below -1");
    if (bsp.visibility.numClusters > 0 && f.cluster >= bsp.visibility.numClusters)
      leafs.checkIndex(i, "cluster", f.cluster, -1, bsp.visibility.numClusters);
    if (f.area < -1) leafs.fail(i, "area " + std::to_string(f.area) + " below -1");
    leafs.checkRange(i, "leaf surfaces", f.firstLeafSurface, f.numLeafSurfaces, bsp.leafSurfaces.size());
    leafs.checkRange(i, "leaf brushes", f.firstLeafBrush, f.numLeafBrushes, bsp.leafBrushes.size());
  }

  const auto leafSurfaces = lump(BspLump::LeafSurfaces);
  for (size_t i = 0; i < bsp.leafSurfaces.size(); ++i)
    leafSurfaces.checkIndex(i, "surface", bsp.leafSurfaces[i], 0, bsp.surfaces.size());
  const auto leafBrushes = lump(BspLump::LeafBrushes);
  for (size_t i = 0; i < bsp.leafBrushes.size(); ++i)
    leafBrushes.checkIndex(i, "brush", bsp.leafBrushes[i], 0, bsp.brushes.size());

  const auto models = lump(BspLump::Models);
  if (bsp.models.empty()) r.fail("lump models", "no world model (model 0)");
  for (size_t i = 0; i < bsp.models.size(); ++i) {
    const auto& m = bsp.models[i];
    models.checkRange(i, "surfaces", m.firstSurface, m.numSurfaces, bsp.surfaces.size());
    models.checkRange(i, "brushes", m.firstBrush, m.numBrushes, bsp.brushes.size());
  }

  const auto brushes = lump(BspLump::Brushes);
  for (size_t i = 0; i < bsp.brushes.size(); ++i) {
    const auto& b = bsp.brushes[i];
    brushes.checkRange(i, "sides", b.firstSide, b.numSides, bsp.brushSides.size());
    brushes.checkIndex(i, "shader", b.shader, 0, bsp.shaders.size());
  }
  const auto sides = lump(BspLump::BrushSides);
  for (size_t i = 0; i < bsp.brushSides.size(); ++i) {
    sides.checkIndex(i, "plane", bsp.brushSides[i].plane, 0, bsp.planes.size());
    sides.checkIndex(i, "shader", bsp.brushSides[i].shader, 0, bsp.shaders.size());
  }

  const auto fogs = lump(BspLump::Fogs);
  for (size_t i = 0; i < bsp.fogs.size(); ++i) {
    const auto& f = bsp.fogs[i];
    fogs.checkIndex(i, "brush", f.brush, 0, bsp.brushes.size());
    if (f.visibleSide != -1)
      fogs.checkIndex(i, "visible side", f.visibleSide, 0,
                      static_cast<size_t>(bsp.brushes[f.brush].numSides));
  }

  const auto surfaces = lump(BspLump::Surfaces);
  size_t badFogs = 0;
  for (size_t i = 0; i < bsp.surfaces.size(); ++i) {
    auto& s = bsp.surfaces[i];
    surfaces.checkIndex(i, "shader", s.shader, 0, bsp.shaders.size());
    if (s.fog != -1 && (s.fog < 0 || static_cast<size_t>(s.fog) >= bsp.fogs.size())) {
      // Some shipped maps reference fog 0 with no fogs; the engine treats it as "no fog".
      s.fog = -1;
      ++badFogs;
    }
    // Any lightmap number loads: lightmapPageOf() decides which ones select a page.
    if (s.type == SurfaceType::Flare) continue;  // flares carry no geometry we use
    surfaces.checkRange(i, "vertices", s.firstVert, s.numVerts, bsp.drawVerts.size());
    if (s.type == SurfaceType::Patch) {
      const auto dimOk = [](int32_t d) { return d >= 3 && d <= kMaxPatchSize && (d & 1) == 1; };
      if (!dimOk(s.patchWidth) || !dimOk(s.patchHeight))
        surfaces.fail(i, "patch size " + std::to_string(s.patchWidth) + "x" +
                             std::to_string(s.patchHeight) + " is not odd in [3, 31]");
      if (static_cast<int64_t>(s.patchWidth) * s.patchHeight != s.numVerts)
        surfaces.fail(i, "patch size " + std::to_string(s.patchWidth) + "x" +
                             std::to_string(s.patchHeight) + " does not match " +
                             std::to_string(s.numVerts) + " vertices");
      continue;
    }
    surfaces.checkRange(i, "indexes", s.firstIndex, s.numIndexes, bsp.drawIndexes.size());
    if (s.numIndexes % 3 != 0)
      surfaces.fail(i, std::to_string(s.numIndexes) + " indexes is not a multiple of 3");
    for (int32_t k = 0; k < s.numIndexes; ++k)
      surfaces.checkIndex(i, "vertex index", bsp.drawIndexes[s.firstIndex + k], 0,
                          static_cast<size_t>(s.numVerts));
  }
  if (badFogs)
    bsp.warnings.push_back("surfaces: " + std::to_string(badFogs) +
                           " fog numbers outside the fogs lump treated as no fog");
}

BspVisibility decodeVisibility(const ByteReader& r, LumpRange range) {
  BspVisibility vis;
  if (range.length == 0) return vis;
  const char* field = "lump visibility";
  if (range.length < 8)
    r.fail(field, std::to_string(range.length) + " bytes cannot hold the 8-byte header");
  const auto numClusters = r.read<int32_t>(range.offset, field);
  const auto bytesPerCluster = r.read<int32_t>(range.offset + 4, field);
  if (numClusters < 0 || bytesPerCluster < 0)
    r.fail(field, "negative cluster count or row size");
  if (static_cast<int64_t>(bytesPerCluster) * 8 < numClusters)
    r.fail(field, "row of " + std::to_string(bytesPerCluster) + " bytes cannot hold " +
                      std::to_string(numClusters) + " clusters");
  const uint64_t rowBytes = static_cast<uint64_t>(numClusters) * static_cast<uint64_t>(bytesPerCluster);
  if (rowBytes > range.length - 8)
    r.fail(field, std::to_string(numClusters) + " rows of " + std::to_string(bytesPerCluster) +
                      " bytes exceed the lump of " + std::to_string(range.length) + " bytes");
  const auto rows = r.bytes(range.offset + 8, rowBytes, field);
  vis.numClusters = numClusters;
  vis.bytesPerCluster = bytesPerCluster;
  vis.rows.resize(rows.size());
  if (!rows.empty()) std::memcpy(vis.rows.data(), rows.data(), rows.size());
  return vis;
}

/// Grid points span model 0's bounds snapped inwards to the grid, as the engine does.
BspLightGrid decodeLightGrid(BspFile& bsp, std::span<const std::byte> raw) {
  BspLightGrid grid;
  grid.raw.resize(raw.size());
  if (!raw.empty()) std::memcpy(grid.raw.data(), raw.data(), raw.size());
  try {
    const auto world = findWorldspawn(parseEntities(bsp.entities, bsp.fileName));
    if (world) grid.gridSize = worldspawnGridSize(*world, bsp.warnings);
  } catch (const FormatError& e) {
    bsp.warnings.push_back(std::string("light grid uses default gridsize: ") + e.what());
  }
  const auto& world = bsp.models.front();
  int64_t points = 1;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::ceil(static_cast<double>(world.mins[k]) / grid.gridSize[k]) * grid.gridSize[k];
    const double hi = std::floor(static_cast<double>(world.maxs[k]) / grid.gridSize[k]) * grid.gridSize[k];
    const double n = std::floor((hi - lo) / grid.gridSize[k]) + 1;
    grid.origin[k] = static_cast<float>(lo);
    grid.dims[k] = (n >= 1 && n < 1e6) ? static_cast<int>(n) : 0;
    points *= grid.dims[k];
  }
  grid.valid = points > 0 && !grid.raw.empty() &&
               static_cast<uint64_t>(points) * kLightGridPointSize == grid.raw.size();
  if (!grid.raw.empty() && !grid.valid)
    bsp.warnings.push_back("light grid: " + std::to_string(grid.raw.size()) + " bytes do not match " +
                           std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" +
                           std::to_string(grid.dims.z) + " points of 8 bytes; grid ignored");
  return grid;
}

}  // namespace

const char* bspLumpName(BspLump lump) {
  static constexpr const char* kNames[] = {
      "entities", "shaders", "planes", "nodes", "leafs", "leaf surfaces", "leaf brushes", "models",
      "brushes", "brush sides", "draw verts", "draw indexes", "fogs", "surfaces", "lightmaps",
      "light grid", "visibility"};
  const int i = static_cast<int>(lump);
  return (i >= 0 && i < 17) ? kNames[i] : "unknown lump";
}

bool BspVisibility::clusterVisible(int32_t from, int32_t to) const {
  if (numClusters == 0 || from < 0 || to < 0 || from >= numClusters || to >= numClusters)
    return true;
  const size_t byte = static_cast<size_t>(from) * bytesPerCluster + static_cast<size_t>(to >> 3);
  return (rows[byte] >> (to & 7)) & 1;
}

int32_t lightmapPageOf(int32_t lightmap, size_t pages) {
  return lightmap >= 0 && static_cast<size_t>(lightmap) < pages ? lightmap : -1;
}

std::span<const uint8_t> BspFile::lightmapPage(size_t index) const {
  constexpr size_t kPage = kLightmapSize * kLightmapSize * 3;
  if (index >= numLightmaps()) throw std::out_of_range("lightmap page " + std::to_string(index));
  return std::span<const uint8_t>(lightmaps).subspan(index * kPage, kPage);
}

int32_t BspFile::modelOfSurface(size_t surfaceIndex) const {
  for (size_t m = 0; m < models.size(); ++m) {
    const auto first = static_cast<size_t>(models[m].firstSurface);
    if (surfaceIndex >= first && surfaceIndex < first + static_cast<size_t>(models[m].numSurfaces))
      return static_cast<int32_t>(m);
  }
  return -1;
}

BspFile parseBsp(std::span<const std::byte> bytes, std::string fileName) {
  const ByteReader reader(bytes, fileName);
  const auto lumps = readLumpTable(reader);
  BspFile bsp;
  bsp.fileName = std::move(fileName);
  {
    const auto text = reader.bytes(lumps[0].offset, lumps[0].length, "lump entities");
    size_t n = 0;  // the lump is NUL-terminated; keep only the text before the first NUL
    while (n < text.size() && text[n] != std::byte{0}) ++n;
    bsp.entities.assign(reinterpret_cast<const char*>(text.data()), n);
  }
  decodeGeometryLumps(bsp, reader, lumps);
  bsp.visibility = decodeVisibility(reader, lumps[static_cast<int>(BspLump::Visibility)]);
  validateReferences(bsp, reader, lumps);
  const auto& gridRange = lumps[static_cast<int>(BspLump::LightGrid)];
  bsp.lightGrid = decodeLightGrid(bsp, reader.bytes(gridRange.offset, gridRange.length, "lump light grid"));
  return bsp;
}

}  // namespace q3
