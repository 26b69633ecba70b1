// The sampling igms-dyn bench times a kernel with, shared with the peer
// benchmark (bench/peer_bench.cc) so that igms and its peers are measured alike.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace igms::dyn {

// Median over 301 samples of the mean time of one call, in microseconds; call(k) with k cycling over
// `states` prepared inputs, enough calls per sample for it to last about 50 us.
inline double medianMicroseconds(const std::function<void(int)>& call, int states) {
  using clock = std::chrono::steady_clock;
  int per_sample = 1;
  for (;;) {
    const auto t0 = clock::now();
    for (int k = 0; k < per_sample; ++k) call(k % states);
    const double us = std::chrono::duration<double, std::micro>(clock::now() - t0).count();
    if (us > 50.0 || per_sample > (1 << 20)) break;
    per_sample *= 2;
  }
  std::vector<double> samples;
  for (int s = 0; s < 301; ++s) {
    const auto t0 = clock::now();
    for (int k = 0; k < per_sample; ++k) call((s + k) % states);
    samples.push_back(std::chrono::duration<double, std::micro>(clock::now() - t0).count() / per_sample);
  }
  std::nth_element(samples.begin(), samples.begin() + static_cast<long>(samples.size() / 2), samples.end());
  return samples[samples.size() / 2];
}

}  // namespace igms::dyn
