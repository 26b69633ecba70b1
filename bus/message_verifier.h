// Checks messages before anything decodes them. With a bus key, a message is
// accepted only when its tag holds under its sender's key and its counter is
// new for that sender on that channel: newer than any seen, or one of the
// kWindow before the newest not seen yet (an IPsec-style window, so the
// reordering of a jittery link is no replay: 20 ms of jitter reorders a 1 kHz
// stream's catch-up bursts by more than 64), and signed within kMaxAgeS of
// now by the receiver's clock. A sender silent for longer than that gives its
// place to a new one when the table is full: whatever of it was captured is
// stale by then, so a restarted program never runs out of places and an old
// message never comes back. Refusals are counted by reason. Without a key
// everything is accepted (the unauthenticated bus), and signed messages are
// counted so the program can say it lacks the key. One verifier per receiving
// thread; the counts may be read from any thread. Checking allocates nothing:
// the sender and stream tables are preallocated.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_signature.h"

namespace igms::bus {

enum class Refusal : int { kUnsigned = 0, kBadSignature = 1, kReplayed = 2, kTooManySenders = 3, kStale = 4 };
inline constexpr int kRefusals = 5;
const char* refusalName(Refusal r);  // "unsigned", "bad_signature", "replayed", "too_many_senders", "stale"

struct Verdict {
  bool accepted = false;
  Refusal why = Refusal::kUnsigned;  // when refused
  size_t payload_bytes = 0;          // the LCM message without the trailer, when accepted
};

struct VerifierCounts {
  int64_t accepted = 0;
  std::array<int64_t, kRefusals> refused{};
  int64_t signed_unchecked = 0;  // signed messages taken by a verifier without a key
  int64_t refusedTotal() const;
};

class MessageVerifier {
 public:
  static constexpr int kMaxSenders = 256;   // processes heard with a valid signature within kMaxAgeS
  static constexpr int kMaxStreams = 2048;  // (sender, channel) pairs
  static constexpr double kMaxAgeS = 60.0;  // a message signed longer ago (or ahead), by the clocks, is stale
  static constexpr uint64_t kWindow = 1024;  // counters behind the newest still taken once

  // `program` prefixes the one line printed the first time each kind of refusal happens.
  MessageVerifier(std::optional<BusKey> key, std::string program);
  ~MessageVerifier();
  MessageVerifier(const MessageVerifier&) = delete;
  MessageVerifier& operator=(const MessageVerifier&) = delete;

  Verdict check(std::string_view channel, const uint8_t* data, size_t size);
  // The same at a given time: now_us on the wall clock of the trailers, steady_s on a monotonic one (tests).
  Verdict checkAt(std::string_view channel, const uint8_t* data, size_t size, int64_t now_us, double steady_s);
  bool keyed() const { return key_.has_value(); }
  VerifierCounts counts() const;
  // "accepted 1200, refused 3 (bad_signature 3)": for a program's exit line.
  std::string summary() const;
  // Silences the first-refusal lines (tests that refuse on purpose).
  void quiet() { quiet_ = true; }

 private:
  struct Sender;
  struct Stream {
    int sender = -1;
    uint64_t channel = 0;  // FNV-1a of the name
    uint64_t newest = 0;
    std::array<uint64_t, kWindow / 64> seen{};  // bit (c % kWindow): counter c was accepted (within the window)
  };
  static bool seenBit(const Stream& s, uint64_t c) { return s.seen[c % kWindow / 64] >> (c % 64) & 1; }
  static void setBit(Stream& s, uint64_t c) { s.seen[c % kWindow / 64] |= uint64_t{1} << (c % 64); }
  Verdict refuse(Refusal why, std::string_view channel);
  bool acceptCounter(int sender, std::string_view channel, uint64_t counter, Refusal* why);
  int placeFor(double steady_s);  // a free sender place, or an idle sender's; -1 when none

  std::optional<BusKey> key_;
  std::unique_ptr<SenderKeys> keys_;
  std::string program_;
  bool quiet_ = false;
  std::vector<std::unique_ptr<Sender>> senders_;
  int nsenders_ = 0;
  std::unique_ptr<Sender> scratch_;  // a new sender's check, before it has a place
  std::vector<Stream> streams_;
  int nstreams_ = 0;
  std::atomic<int64_t> accepted_{0}, signed_unchecked_{0};
  std::array<std::atomic<int64_t>, kRefusals> refused_{};
  std::array<std::atomic<bool>, kRefusals + 1> told_{};  // the last: signed messages without a key
};

}  // namespace igms::bus
