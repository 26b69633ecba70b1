// The LCM event-log format (what lcm-logger writes and lcm-logplayer,
// lcm::LogFile and Python's lcm.EventLog read), with our own reader so that a
// damaged log names the byte offset of the damage and everything before it
// stays usable.
//
// The reader also takes gzip-compressed logs (*.lcmlog.gz), transparently.
//
// Each event, big-endian: sync word 0xEDA1DA01, event number (int64),
// timestamp in microseconds (int64), channel length (int32), data length
// (int32), channel bytes, data bytes.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace igms::log {

struct Event {
  int64_t number = 0;
  int64_t utime = 0;
  std::string channel;
  std::vector<uint8_t> data;
  uint64_t offset = 0;  // byte offset of the event in the file
};

class LogError : public std::runtime_error {
 public:
  LogError(const std::string& what, uint64_t offset) : std::runtime_error(what), offset(offset) {}
  uint64_t offset;
};

class LogWriter {
 public:
  // Throws std::runtime_error when the file cannot be created.
  explicit LogWriter(const std::string& path);
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;
  void write(int64_t utime, const std::string& channel, const uint8_t* data, size_t size);
  void flush();
  uint64_t bytes() const { return bytes_; }
  int64_t events() const { return next_number_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  int64_t next_number_ = 0;
  uint64_t bytes_ = 0;
};

class LogReader {
 public:
  // Throws LogError (offset 0) when the file cannot be opened.
  explicit LogReader(const std::string& path);
  ~LogReader();
  LogReader(const LogReader&) = delete;
  LogReader& operator=(const LogReader&) = delete;
  // The next event into *e; false at a clean end of file. Throws LogError
  // with the byte offset at a bad sync word or a truncated event.
  bool next(Event* e);
  void rewind();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  void* file_ = nullptr;  // a zlib gzFile
  uint64_t offset_ = 0;
};

// All events of a log; on damage, the events before it and the error.
struct LogContents {
  std::vector<Event> events;
  bool damaged = false;
  std::string error;
  uint64_t error_offset = 0;
};
LogContents readAll(const std::string& path);

}  // namespace igms::log
