// Writes the seed corpus of the pk3 fuzzer: small zip archives built by code (no game data),
// covering what physfs's zip reader and the VFS index handle: stored and deflated entries
// (stored and fixed-Huffman deflate blocks), directory entries, nested and mixed-case paths,
// data descriptors, extra fields, an archive comment, zip64 records and hostile entry names.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

/// How an entry's data is stored.
enum class Method { kStored, kDeflateStoredBlock, kDeflateFixed };

/// One archive member.
struct Entry {
  std::string name;
  std::string data;
  Method method = Method::kStored;
  bool dataDescriptor = false;  ///< sizes and CRC after the data (general purpose bit 3)
  bool zip64 = false;           ///< 32-bit sizes and offset set to 0xFFFFFFFF, real ones in a zip64 extra field
  std::string extra;            ///< extra field bytes added to both headers
};

uint32_t crc32(const std::string& data) {
  uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char c : data) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void u16(std::string& s, uint32_t v) {
  s.push_back(static_cast<char>(v & 0xFF));
  s.push_back(static_cast<char>((v >> 8) & 0xFF));
}
void u32(std::string& s, uint32_t v) { u16(s, v & 0xFFFF), u16(s, v >> 16); }
void u64(std::string& s, uint64_t v) { u32(s, static_cast<uint32_t>(v)), u32(s, static_cast<uint32_t>(v >> 32)); }

/// Least-significant-bit-first bit writer (deflate's order).
struct BitWriter {
  std::string out;
  int used = 8;
  void bits(uint32_t value, int count) {  // value's low bits, first bit first
    for (int i = 0; i < count; ++i) {
      if (used == 8) out.push_back(0), used = 0;
      out.back() = static_cast<char>(out.back() | (((value >> i) & 1u) << used++));
    }
  }
  void huffman(uint32_t code, int length) {  // Huffman codes go most-significant bit first
    for (int i = length - 1; i >= 0; --i) bits((code >> i) & 1u, 1);
  }
};

/// Deflate stream of one fixed-Huffman block with literals only.
std::string deflateFixed(const std::string& data) {
  BitWriter w;
  w.bits(1, 1);  // final block
  w.bits(1, 2);  // fixed Huffman
  for (unsigned char c : data) c < 144 ? w.huffman(0x30 + c, 8) : w.huffman(0x190 + (c - 144), 9);
  w.huffman(0, 7);  // end of block (code 256)
  return w.out;
}

/// Deflate stream of stored blocks of at most `blockSize` bytes.
std::string deflateStored(const std::string& data, size_t blockSize) {
  std::string out;
  size_t at = 0;
  do {
    const size_t n = std::min(blockSize, data.size() - at);
    out.push_back(at + n == data.size() ? 1 : 0);  // BFINAL, BTYPE 00, padding
    u16(out, static_cast<uint32_t>(n));
    u16(out, static_cast<uint32_t>(~n & 0xFFFF));
    out += data.substr(at, n);
    at += n;
  } while (at < data.size());
  return out;
}

std::string zip(const std::vector<Entry>& entries, const std::string& comment = "", bool zip64End = false) {
  std::string out, central;
  for (const Entry& e : entries) {
    const uint32_t offset = static_cast<uint32_t>(out.size());
    const std::string packed = e.method == Method::kStored           ? e.data
                               : e.method == Method::kDeflateFixed ? deflateFixed(e.data)
                                                                    : deflateStored(e.data, 7);
    const uint16_t method = e.method == Method::kStored ? 0 : 8;
    const uint16_t flags = e.dataDescriptor ? 8 : 0;
    const uint32_t crc = crc32(e.data);
    const uint32_t size = static_cast<uint32_t>(e.data.size()), csize = static_cast<uint32_t>(packed.size());
    std::string extra = e.extra;
    if (e.zip64) {
      u16(extra, 1), u16(extra, 24);
      u64(extra, size), u64(extra, csize), u64(extra, offset);
    }
    const uint32_t s32 = e.zip64 ? 0xFFFFFFFFu : size, c32 = e.zip64 ? 0xFFFFFFFFu : csize;
    const uint16_t version = e.zip64 ? 45 : 20;
    u32(out, 0x04034b50), u16(out, version), u16(out, flags), u16(out, method), u16(out, 0), u16(out, 0x21);
    u32(out, e.dataDescriptor ? 0 : crc), u32(out, e.dataDescriptor ? 0 : c32), u32(out, e.dataDescriptor ? 0 : s32);
    u16(out, static_cast<uint32_t>(e.name.size())), u16(out, static_cast<uint32_t>(extra.size()));
    out += e.name + extra + packed;
    if (e.dataDescriptor) u32(out, 0x08074b50), u32(out, crc), u32(out, csize), u32(out, size);
    u32(central, 0x02014b50), u16(central, 0x031E), u16(central, version), u16(central, flags), u16(central, method);
    u16(central, 0), u16(central, 0x21), u32(central, crc), u32(central, c32), u32(central, s32);
    u16(central, static_cast<uint32_t>(e.name.size())), u16(central, static_cast<uint32_t>(extra.size()));
    u16(central, 0), u16(central, 0), u16(central, 0);
    u32(central, e.name.back() == '/' ? 0x41ED0010u : 0x81A40000u);  // unix mode: directory or file
    u32(central, e.zip64 ? 0xFFFFFFFFu : offset);
    central += e.name + extra;
  }
  const uint64_t centralOffset = out.size();
  out += central;
  if (zip64End) {
    const uint64_t recordOffset = out.size();
    u32(out, 0x06064b50), u64(out, 44), u16(out, 45), u16(out, 45), u32(out, 0), u32(out, 0);
    u64(out, entries.size()), u64(out, entries.size()), u64(out, central.size()), u64(out, centralOffset);
    u32(out, 0x07064b50), u32(out, 0), u64(out, recordOffset), u32(out, 1);
  }
  u32(out, 0x06054b50), u16(out, 0), u16(out, 0);
  u16(out, zip64End ? 0xFFFF : static_cast<uint32_t>(entries.size()));
  u16(out, zip64End ? 0xFFFF : static_cast<uint32_t>(entries.size()));
  u32(out, static_cast<uint32_t>(central.size())), u32(out, zip64End ? 0xFFFFFFFFu : static_cast<uint32_t>(centralOffset));
  u16(out, static_cast<uint32_t>(comment.size()));
  return out + comment;
}

void write(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;  // output folder
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  const std::string shader = "textures/x/wall\n{\n\t{\n\t\tmap textures/x/wall.tga\n\t}\n}\n";

  write(dir / "basic.pk3", zip({{"scripts/x.shader", shader}, {"maps/x.bsp", "IBSP\x2e"}, {"textures/x/wall.tga", "TGA"}}));
  write(dir / "deflate_fixed.pk3", zip({{"scripts/x.shader", shader, Method::kDeflateFixed},
                                        {"levelshots/x.tga", std::string(40, '\xC8'), Method::kDeflateFixed}}));
  write(dir / "deflate_stored_blocks.pk3", zip({{"scripts/x.shader", shader, Method::kDeflateStoredBlock},
                                                {"empty.cfg", "", Method::kDeflateStoredBlock}}));
  write(dir / "directories.pk3", zip({{"models/", ""},
                                      {"models/players/", ""},
                                      {"models/players/x/head.md3", "IDP3"},
                                      {"models/players/x/head_default.skin", "h_head,head.tga\n"},
                                      {"Scripts/A.shader", "upper"},
                                      {"scripts/a.shader", "lower"}}));
  write(dir / "data_descriptor.pk3", zip({{"scripts/x.shader", shader, Method::kDeflateFixed, true},
                                          {"maps/x.bsp", "IBSP", Method::kStored, true}}));
  write(dir / "extra_and_comment.pk3",
        zip({{"sound/x.wav", "RIFF", Method::kStored, false, false, std::string("\x55\x54\x05\x00\x01\x00\x00\x00\x00", 9)}},
            "archive comment"));
  write(dir / "zip64.pk3", zip({{"maps/big.bsp", "IBSP", Method::kStored, false, true},
                                {"scripts/x.shader", shader, Method::kDeflateFixed, false, true}},
                               "", true));
  write(dir / "empty.pk3", zip({}));
  write(dir / "odd_names.pk3", zip({{"gfx\\2d\\x.tga", "backslashes"},
                                    {"../escape.cfg", "up"},
                                    {"/absolute.cfg", "abs"},
                                    {"dir//double.cfg", "double"},
                                    {"./dot.cfg", "dot"},
                                    {"maps/x.bsp", "shadow"},
                                    {"MAPS/X.BSP", "case twin"}}));
  return 0;
}
