// A model's frame (link) names, sorted once, so that a name becomes its frame
// index in O(log n) without allocating: the bus edge resolves every input's
// link names with it (Model::frameIndex scans every frame). Equal names, were
// there any, give the lowest index, as frameIndex does.
#pragma once

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/model/model.h"

namespace igms {

class FrameNames {
 public:
  explicit FrameNames(const Model& model) {
    sorted_.reserve(model.frames.size());
    for (size_t f = 0; f < model.frames.size(); ++f) sorted_.emplace_back(model.frames[f].name, static_cast<int>(f));
    std::sort(sorted_.begin(), sorted_.end());
  }
  // The frame named `name`; -1 when the model has none.
  int find(const std::string& name) const {
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), name,
                                     [](const std::pair<std::string, int>& e, const std::string& n) { return e.first < n; });
    return it != sorted_.end() && it->first == name ? it->second : -1;
  }

 private:
  std::vector<std::pair<std::string, int>> sorted_;  // (name, frame index), by name then index
};

}  // namespace igms
