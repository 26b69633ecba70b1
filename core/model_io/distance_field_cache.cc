#include "core/model_io/distance_field_cache.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace igms {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'I', 'G', 'M', 'S', 'S', 'D', 'F', '2'};

struct Header {
  char magic[8];
  uint64_t key;
  int32_t nx, ny, nz, pad;
  double origin[3], spacing, band;
};

void hashBytes(uint64_t& h, const void* data, size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
}

fs::path folder() {
  if (const char* d = std::getenv("IGMS_CACHE_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "igms";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "igms";
  return {};
}

fs::path fileFor(uint64_t key) {
  const fs::path dir = folder();
  if (dir.empty()) return {};
  char name[40];
  std::snprintf(name, sizeof name, "field-%016llx.sdf", static_cast<unsigned long long>(key));
  return dir / "fields" / name;
}

}  // namespace

uint64_t distanceFieldKey(const TriangleMesh& mesh, double spacing, double band) {
  uint64_t h = 14695981039346656037ull;
  hashBytes(h, kMagic, sizeof kMagic);
  for (const Vector3& v : mesh.vertices) hashBytes(h, v.data(), 3 * sizeof(double));
  for (const auto& t : mesh.triangles) hashBytes(h, t.data(), 3 * sizeof(int));
  hashBytes(h, &spacing, sizeof spacing);
  hashBytes(h, &band, sizeof band);
  return h;
}

std::optional<DistanceField> readCachedField(uint64_t key) {
  const fs::path file = fileFor(key);
  if (file.empty()) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  Header h{};
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 ||
      h.key != key || h.nx <= 0 || h.ny <= 0 || h.nz <= 0 || h.nx > 4096 || h.ny > 4096 || h.nz > 4096)
    return std::nullopt;
  DistanceField f;
  f.nx = h.nx;
  f.ny = h.ny;
  f.nz = h.nz;
  f.origin = Vector3(h.origin[0], h.origin[1], h.origin[2]);
  f.spacing = h.spacing;
  f.band = h.band;
  f.values.resize(static_cast<size_t>(h.nx) * static_cast<size_t>(h.ny) * static_cast<size_t>(h.nz));
  f.nearest.resize(f.values.size());
  if (!in.read(reinterpret_cast<char*>(f.values.data()), static_cast<std::streamsize>(f.values.size() * sizeof(float))) ||
      !in.read(reinterpret_cast<char*>(f.nearest.data()), static_cast<std::streamsize>(f.nearest.size() * sizeof(int32_t))))
    return std::nullopt;
  return f;
}

void writeCachedField(uint64_t key, const DistanceField& f) {
  const fs::path file = fileFor(key);
  if (file.empty()) return;
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  if (ec) return;
  const fs::path tmp = file.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) return;
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.key = key;
    h.nx = f.nx;
    h.ny = f.ny;
    h.nz = f.nz;
    for (int i = 0; i < 3; ++i) h.origin[i] = f.origin[i];
    h.spacing = f.spacing;
    h.band = f.band;
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(f.values.data()), static_cast<std::streamsize>(f.values.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(f.nearest.data()), static_cast<std::streamsize>(f.nearest.size() * sizeof(int32_t)));
    if (!out) {
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, file, ec);  // atomic: a reader sees the old file or the whole new one
  if (ec) fs::remove(tmp, ec);
}

}  // namespace igms
