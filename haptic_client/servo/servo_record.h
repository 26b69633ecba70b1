// What the hand felt, cycle by cycle (igms-haptic --record FILE): the tip, the force the physics
// asked for and the force the device rendered, into rows allocated before the loop starts and
// written as CSV after it ends, so the servo loop does no I/O and no allocation. A run longer than
// the rows allocated keeps its first rows and counts the rest.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/model/spatial.h"

namespace igms {

struct ServoRecordRow {
  double t = 0.0;              // s since the loop started
  double estimate_time = 0.0;  // simulated time of the estimate the force was computed against
  int mode = 0;                // haptic_input_t.MODE_* sent this cycle
  Vector3 tip = Vector3::Zero();       // scene frame, m
  Vector3 proxy = Vector3::Zero();     // the tip's proxy, scene frame, m
  Vector3 on_user = Vector3::Zero();   // the coupling's force on the hand, N (before the guards)
  Vector3 rendered = Vector3::Zero();  // what the device was told to render, N
};

class ServoRecord {
 public:
  // rows: how many cycles to keep (0: record nothing).
  explicit ServoRecord(int64_t rows = 0) { rows_.reserve(static_cast<size_t>(rows)); }
  bool on() const { return rows_.capacity() > 0; }
  void add(const ServoRecordRow& row) {
    if (rows_.size() < rows_.capacity()) rows_.push_back(row);
    else ++dropped_;
  }
  int64_t dropped() const { return dropped_; }
  const std::vector<ServoRecordRow>& rows() const { return rows_; }
  // The rows as CSV; false (and why in *error) when the file cannot be written.
  bool write(const std::string& path, std::string* error) const;

 private:
  std::vector<ServoRecordRow> rows_;
  int64_t dropped_ = 0;
};

}  // namespace igms
