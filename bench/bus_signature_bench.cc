// igms-bus-bench: what signing the bus costs. For each message the programs
// send (a haptic input, the robot state of the PUMA, the Go1 and Talos, the
// largest datagram), the median time to sign it (bus::MessageSigner:
// AES-256-GMAC) and to check it (bus::MessageVerifier: the tag and the replay
// window), each against the peer an HMAC design would use (OpenSSL's
// HMAC-SHA256 over the same bytes) in the same run, interleaved; the ratio is
// printed. The budget: <= 2 us per message at Talos's state.
//   igms-bus-bench [--rounds N]
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bus/message_signer.h"
#include "bus/message_verifier.h"
#include "core/cli/command_line.h"
#include "core/scene/resolved_scene.h"
#include "igms/haptic_input_t.hpp"
#include "server/app/state_publisher.h"

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Message {
  std::string name;
  std::vector<uint8_t> bytes;
};

template <typename M>
std::vector<uint8_t> encoded(const M& m) {
  std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

volatile uint8_t g_sink = 0;

}  // namespace

int main(int argc, char** argv) {
  int rounds = 21;
  CLI::App app{"", "igms-bus-bench"};
  igms::cli::describe(app, "The signed bus's cost per message: sign and check (AES-256-GMAC) against HMAC-SHA256, "
                           "medians, in the same run.");
  app.add_option("--rounds", rounds, "rounds of 2000 messages each (the median is over the rounds)")
      ->check(CLI::Range(3, 1000));
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;

  std::vector<Message> messages;
  igms::haptic_input_t input{};
  input.contact_link = "link2";
  input.attach_link = "ee_link";
  messages.push_back({"haptic input", encoded(input)});
  for (const char* scene : {"puma_obstacle", "go1_stand", "talos_stand"}) {
    const std::string path = std::string(IGMS_SOURCE_DIR) + "/scenes/" + scene + ".yaml";
    try {
      const igms::ResolvedScene r = igms::resolveScene(igms::loadScene(path));
      messages.push_back({std::string("robot state, ") + scene, encoded(igms::sizedStateMessage(*r.model))});
    } catch (const std::exception& e) {
      std::printf("(left out %s: %s)\n", scene, e.what());
    }
  }
  messages.push_back({"the largest datagram", std::vector<uint8_t>(igms::kMaxDatagramBytes, 7)});

  igms::bus::BusKey key{};
  for (size_t i = 0; i < key.size(); ++i) key[i] = static_cast<uint8_t>(i * 13 + 1);
  igms::bus::MessageSigner signer(key);
  igms::bus::MessageVerifier verifier(key, "igms-bus-bench");
  verifier.quiet();  // the forged row refuses on purpose
  std::printf("%-34s %7s  %9s %9s  %9s  %s\n", "message", "bytes", "sign us", "check us", "HMAC us", "HMAC / sign");
  constexpr int kPerRound = 2000;
  for (const Message& m : messages) {
    const size_t n = m.bytes.size();
    std::vector<std::vector<uint8_t>> signed_copies(kPerRound, std::vector<uint8_t>(n + igms::bus::kTrailerBytes));
    std::vector<double> sign_us, check_us, hmac_us;
    for (int r = 0; r < rounds; ++r) {
      for (auto& b : signed_copies) std::copy(m.bytes.begin(), m.bytes.end(), b.begin());
      auto t0 = Clock::now();
      for (auto& b : signed_copies) signer.sign("IGMS_ROBOT_STATE", b.data(), n);
      sign_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / kPerRound);
      t0 = Clock::now();
      int accepted = 0;
      for (auto& b : signed_copies) accepted += verifier.check("IGMS_ROBOT_STATE", b.data(), b.size()).accepted;
      check_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / kPerRound);
      if (accepted != kPerRound) {
        std::fprintf(stderr, "igms-bus-bench: %d of %d checks failed\n", kPerRound - accepted, kPerRound);
        return 1;
      }
      uint8_t tag[32];
      unsigned length = 0;
      t0 = Clock::now();
      for (auto& b : signed_copies) {
        HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), b.data(), n, tag, &length);
        g_sink = static_cast<uint8_t>(g_sink ^ tag[0]);
      }
      hmac_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / kPerRound);
    }
    const double s = median(sign_us), c = median(check_us), h = median(hmac_us);
    std::printf("%-34s %7zu  %9.3f %9.3f  %9.3f  %.2f\n", m.name.c_str(), n, s, c, h, h / s);
  }
  // A flood's forgery: a haptic input with a trailer of a new random sender each time, so the verifier
  // derives that sender's key before the tag fails (the dearest refusal).
  std::vector<double> forged_us;
  std::vector<std::vector<uint8_t>> forged(kPerRound, messages[0].bytes);
  uint64_t x = 88172645463325252ull;
  for (int r = 0; r < rounds; ++r) {
    for (auto& b : forged) {
      b.resize(messages[0].bytes.size());
      b.insert(b.end(), igms::bus::kMagic, igms::bus::kMagic + sizeof igms::bus::kMagic);
      for (size_t i = 0; i < igms::bus::kTrailerBytes - sizeof igms::bus::kMagic; ++i) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        b.push_back(static_cast<uint8_t>(x));
      }
    }
    const auto t0 = Clock::now();
    int refused = 0;
    for (auto& b : forged) refused += !verifier.check("IGMS_HAPTIC_INPUT", b.data(), b.size()).accepted;
    forged_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / kPerRound);
    if (refused != kPerRound) return 1;
  }
  std::printf("%-34s %7zu  %9s %9.3f\n", "haptic input, forged sender", messages[0].bytes.size() + igms::bus::kTrailerBytes, "",
              median(forged_us));
  return 0;
}
