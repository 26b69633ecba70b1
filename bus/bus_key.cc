#include "bus/bus_key.h"

#include <fcntl.h>
#include <openssl/rand.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <stdexcept>

namespace igms::bus {
namespace {

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

std::runtime_error keyError(const std::string& path, const std::string& what) {
  return std::runtime_error("bus key file " + path + ": " + what);
}

}  // namespace

BusKey loadBusKey(const std::string& path) {
  // Opened once, not followed if a link, and checked on the descriptor that is read (a name checked
  // and then opened again can be swapped for a link to another file between the two).
  const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ELOOP) throw keyError(path, "a symbolic link; give the key file itself");
    if (errno == EACCES) throw keyError(path, "not readable by this user (permission denied)");
    throw keyError(path, std::strerror(errno));
  }
  struct Closer {
    int fd;
    ~Closer() { close(fd); }
  } closer{fd};
  struct stat st {};
  if (fstat(fd, &st) != 0) throw keyError(path, std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw keyError(path, "not a regular file");
  if (st.st_uid != geteuid())
    throw keyError(path, "owned by uid " + std::to_string(st.st_uid) + ", not by this user (uid " +
                             std::to_string(geteuid()) + ")");
  // Like ssh with a private key: a key others can read is no secret.
  if (st.st_mode & (S_IRWXG | S_IRWXO)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%03o", static_cast<unsigned>(st.st_mode & 0777));
    throw keyError(path, std::string("readable by others (mode ") + mode + "); chmod 600 it");
  }
  std::string text;
  char chunk[256];
  for (ssize_t n; (n = read(fd, chunk, sizeof chunk)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      throw keyError(path, std::strerror(errno));
    }
    text.append(chunk, static_cast<size_t>(n));
    if (text.size() > 4096) throw keyError(path, "larger than a key file");
  }
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  BusKey key{};
  if (text.size() != 2 * key.size())
    throw keyError(path, "holds " + std::to_string(text.size()) + " characters, not the key's 64 hex digits");
  for (size_t i = 0; i < key.size(); ++i) {
    const int hi = hexDigit(text[2 * i]), lo = hexDigit(text[2 * i + 1]);
    if (hi < 0 || lo < 0) throw keyError(path, "not hex at character " + std::to_string(2 * i + (hi < 0 ? 1 : 2)));
    key[i] = static_cast<uint8_t>(hi * 16 + lo);
  }
  return key;
}

std::optional<BusKey> busKeyFor(const std::string& program, const std::string& path) {
  if (!path.empty()) return loadBusKey(path);
  std::fprintf(stderr, "%s: the bus is unauthenticated (no --key-file, no $%s): any process on this host can "
               "publish on it\n", program.c_str(), kKeyFileEnv);
  return std::nullopt;
}

std::string hexOf(const uint8_t* bytes, size_t n) {
  static const char* digits = "0123456789abcdef";
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    s += digits[bytes[i] >> 4];
    s += digits[bytes[i] & 15];
  }
  return s;
}

void createBusKeyFile(const std::string& path) {
  BusKey key{};
  if (RAND_bytes(key.data(), static_cast<int>(key.size())) != 1) throw keyError(path, "no random bytes (OpenSSL)");
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) throw keyError(path, std::strerror(errno));
  const std::string text = hexOf(key) + "\n";
  const bool ok = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  close(fd);
  if (!ok) throw keyError(path, "could not be written");
}

}  // namespace igms::bus
