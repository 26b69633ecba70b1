#include "tools/eventlog/event_log.h"

#include <cstring>

#include <zlib.h>

namespace igms::log {
namespace {

constexpr uint32_t kSync = 0xEDA1DA01u;
constexpr int32_t kMaxChannel = 256;        // LCM's own limit is 63; generous
constexpr int32_t kMaxData = 256 << 20;     // 256 MiB: anything larger is damage

void put32(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v >> 24); p[1] = static_cast<uint8_t>(v >> 16);
  p[2] = static_cast<uint8_t>(v >> 8); p[3] = static_cast<uint8_t>(v);
}
void put64(uint8_t* p, uint64_t v) {
  put32(p, static_cast<uint32_t>(v >> 32));
  put32(p + 4, static_cast<uint32_t>(v));
}
uint32_t get32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
uint64_t get64(const uint8_t* p) { return (uint64_t{get32(p)} << 32) | get32(p + 4); }

}  // namespace

LogWriter::LogWriter(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "wb")) {
  if (!file_) throw std::runtime_error(path + ": cannot create the log: " + std::strerror(errno));
}

LogWriter::~LogWriter() {
  if (file_) std::fclose(file_);
}

void LogWriter::write(int64_t utime, const std::string& channel, const uint8_t* data, size_t size) {
  uint8_t header[28];
  put32(header, kSync);
  put64(header + 4, static_cast<uint64_t>(next_number_++));
  put64(header + 12, static_cast<uint64_t>(utime));
  put32(header + 20, static_cast<uint32_t>(channel.size()));
  put32(header + 24, static_cast<uint32_t>(size));
  if (std::fwrite(header, 1, sizeof header, file_) != sizeof header ||
      std::fwrite(channel.data(), 1, channel.size(), file_) != channel.size() ||
      (size && std::fwrite(data, 1, size, file_) != size))
    throw std::runtime_error(path_ + ": write failed: " + std::strerror(errno));
  bytes_ += sizeof header + channel.size() + size;
}

void LogWriter::flush() { std::fflush(file_); }

// zlib reads gzip-compressed logs (*.lcmlog.gz) and plain ones alike.
LogReader::LogReader(const std::string& path) : path_(path), file_(gzopen(path.c_str(), "rb")) {
  if (!file_) throw LogError(path + ": cannot open the log: " + std::strerror(errno), 0);
}

LogReader::~LogReader() {
  if (file_) gzclose(static_cast<gzFile>(file_));
}

void LogReader::rewind() {
  gzrewind(static_cast<gzFile>(file_));
  offset_ = 0;
}

bool LogReader::next(Event* e) {
  uint8_t header[28];
  const int read = gzread(static_cast<gzFile>(file_), header, sizeof header);
  if (read <= 0) return false;
  const auto got = static_cast<size_t>(read);
  const uint64_t at = offset_;
  auto fail = [&](const std::string& what) -> bool {
    throw LogError(path_ + ": byte " + std::to_string(at) + ": " + what, at);
  };
  if (got < sizeof header) fail("truncated event header (" + std::to_string(got) + " of 28 bytes)");
  if (get32(header) != kSync) fail("bad sync word (not an LCM event log, or damaged here)");
  const auto channel_len = static_cast<int32_t>(get32(header + 20));
  const auto data_len = static_cast<int32_t>(get32(header + 24));
  if (channel_len <= 0 || channel_len > kMaxChannel) fail("impossible channel length " + std::to_string(channel_len));
  if (data_len < 0 || data_len > kMaxData) fail("impossible data length " + std::to_string(data_len));
  e->number = static_cast<int64_t>(get64(header + 4));
  e->utime = static_cast<int64_t>(get64(header + 12));
  e->channel.resize(static_cast<size_t>(channel_len));
  e->data.resize(static_cast<size_t>(data_len));
  auto readAll = [&](void* dst, size_t n) {
    return gzread(static_cast<gzFile>(file_), dst, static_cast<unsigned>(n)) == static_cast<int>(n);
  };
  if (!readAll(e->channel.data(), e->channel.size()) || (data_len && !readAll(e->data.data(), e->data.size())))
    fail("truncated event (channel '" + e->channel.substr(0, 40) + "', " + std::to_string(data_len) + " data bytes)");
  e->offset = at;
  offset_ += sizeof header + static_cast<uint64_t>(channel_len) + static_cast<uint64_t>(data_len);
  return true;
}

LogContents readAll(const std::string& path) {
  LogContents out;
  try {
    LogReader r(path);
    Event e;
    while (r.next(&e)) out.events.push_back(e);
  } catch (const LogError& err) {
    out.damaged = true;
    out.error = err.what();
    out.error_offset = err.offset;
  }
  return out;
}

}  // namespace igms::log
