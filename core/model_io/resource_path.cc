#include "core/model_io/resource_path.h"

#include <cstdlib>
#include <filesystem>

namespace igms {
namespace fs = std::filesystem;
namespace {

void appendList(const char* env, std::vector<std::string>* out) {
  const char* value = std::getenv(env);
  if (!value) return;
  std::string list(value);
  size_t start = 0;
  while (start <= list.size()) {
    const size_t colon = list.find(':', start);
    const std::string item = list.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    if (!item.empty()) out->push_back(item);
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
}

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string absolutePath(const fs::path& p) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p).lexically_normal().string() : a.string();
}

}  // namespace

std::vector<std::string> packageSearchPath(const std::string& description_path) {
  std::vector<std::string> roots;
  appendList("IGMS_PACKAGE_PATH", &roots);
  appendList("ROS_PACKAGE_PATH", &roots);
  fs::path dir = fs::absolute(fs::path(description_path)).parent_path();
  while (!dir.empty()) {
    roots.push_back(dir.string());
    if (dir == dir.root_path()) break;
    dir = dir.parent_path();
  }
  return roots;
}

ResourceResolution resolveResource(const std::string& uri, const std::string& description_path) {
  ResourceResolution r;
  auto consider = [&](const fs::path& candidate) {
    r.tried.push_back(candidate.string());
    if (!isFile(candidate)) return false;
    r.path = absolutePath(candidate);
    return true;
  };
  static const std::string kPackage = "package://", kFile = "file://";
  if (uri.rfind(kPackage, 0) == 0) {
    const std::string rest = uri.substr(kPackage.size());
    const size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    for (const std::string& root : packageSearchPath(description_path)) {
      // A root may contain the package, or be the package itself.
      if (consider(fs::path(root) / package / inside)) return r;
      if (fs::path(root).filename() == package && consider(fs::path(root) / inside)) return r;
    }
    return r;
  }
  std::string path = uri.rfind(kFile, 0) == 0 ? uri.substr(kFile.size()) : uri;
  fs::path p(path);
  if (p.is_relative()) p = fs::absolute(fs::path(description_path)).parent_path() / p;
  consider(p);
  return r;
}

}  // namespace igms
