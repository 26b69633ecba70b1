// Checks messages before anything decodes them. With a bus key, a message is
// accepted only when its tag holds under its sender's key and its counter is
// new for that sender on that channel: newer than any seen, or one of the
// kWindow before the newest not seen yet (an IPsec-style window, so the
// reordering of a jittery link is no replay: 20 ms of jitter reorders a 1 kHz
// stream's catch-up bursts by more than 64), and signed within kMaxAgeS of
// now by the receiver's clock.
//
// Two clocks meet here: freshness compares the sender's signing time with
// this machine's wall clock, silence is measured on this machine's monotonic
// clock. A sender is forgotten (its place and its streams given to others)
// only after kForgetS = 2 kMaxAgeS of silence: a message it signed is fresh
// for at most kMaxAgeS after its signing time, and that time lies at most
// kMaxAgeS after the message arrived (or it was refused as ahead), so whatever
// of a forgotten sender was captured is stale, however far its clock is ahead.
// Places and streams of forgotten senders are reclaimed when the tables fill,
// so restarted programs and replays never run out of them.
//
// Replayed traffic (igms-replay play, message_signature.h) is refused unless
// the program takes replays (acceptReplays: a logger, a spy, a viewer). A
// program may pin the sender of some channels to the first one it accepts
// (pinSender: a client pins its server, a bus device its device); another
// sender on them is refused. Refusals are counted by reason. Without a key
// everything is accepted (the unauthenticated bus), and signed messages are
// counted so the program can say it lacks the key. One verifier per receiving
// thread; the counts may be read from any thread. Checking allocates nothing:
// the sender and stream tables are preallocated.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_signature.h"

namespace igms::bus {

enum class Refusal : int {
  kUnsigned = 0,
  kBadSignature = 1,
  kReplayed = 2,
  kTooManySenders = 3,
  kStale = 4,
  kReplayedSession = 5,  // a replay's signature (igms-replay play) where replays are not taken
  kOtherSender = 6,      // a pinned channel from another sender than the pinned one
};
inline constexpr int kRefusals = 7;
// "unsigned", "bad_signature", "replayed", "too_many_senders", "stale", "replayed_session", "other_sender"
const char* refusalName(Refusal r);

struct Verdict {
  bool accepted = false;
  Refusal why = Refusal::kUnsigned;  // when refused
  size_t payload_bytes = 0;          // the LCM message without the trailer, when accepted
  // When accepted with a key: who signed it, when (its wall clock, us), and whether as a replay.
  SenderId sender{};
  int64_t signed_us = 0;
  bool replayed = false;
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
  static constexpr double kForgetS = 2 * kMaxAgeS;  // a sender silent this long may be forgotten
  static constexpr uint64_t kWindow = 1024;  // counters behind the newest still taken once
  static constexpr int kMaxPinned = 4;       // channels a program may pin

  // `program` prefixes the one line printed the first time each kind of refusal happens.
  MessageVerifier(std::optional<BusKey> key, std::string program);
  ~MessageVerifier();
  MessageVerifier(const MessageVerifier&) = delete;
  MessageVerifier& operator=(const MessageVerifier&) = delete;

  Verdict check(std::string_view channel, const uint8_t* data, size_t size);
  // The same at a given time: now_us on the wall clock of the trailers, steady_s on a monotonic one (tests).
  Verdict checkAt(std::string_view channel, const uint8_t* data, size_t size, int64_t now_us, double steady_s);
  bool keyed() const { return key_.has_value(); }
  // Takes replayed traffic (igms-replay play) as well as live: for programs that watch, not act.
  void acceptReplays() { accept_replays_ = true; }
  // Pins these channels to one sender: the first whose message on any of them is accepted. Call
  // before the first check; up to kMaxPinned channels.
  void pinSender(std::initializer_list<std::string_view> channels);
  // The sender pinned so far (none yet, or without a key: nullopt).
  std::optional<SenderId> pinned() const;
  // Whether a recorded message's tag holds under the key (its age and counter not looked at):
  // igms-replay's check of what a log holds. False without a key or a trailer.
  bool tagHolds(std::string_view channel, const uint8_t* data, size_t size);
  VerifierCounts counts() const;
  // "accepted 1200, refused 3 (bad_signature 3)": for a program's exit line.
  std::string summary() const;
  // Silences the first-refusal lines (tests that refuse on purpose).
  void quiet() { quiet_ = true; }

 private:
  struct Sender;
  struct Stream {
    int sender = -1;  // -1: free (its sender forgotten)
    uint64_t channel = 0;  // FNV-1a of the name
    uint64_t newest = 0;
    std::array<uint64_t, kWindow / 64> seen{};  // bit (c % kWindow): counter c was accepted (within the window)
  };
  static bool seenBit(const Stream& s, uint64_t c) { return s.seen[c % kWindow / 64] >> (c % 64) & 1; }
  static void setBit(Stream& s, uint64_t c) { s.seen[c % kWindow / 64] |= uint64_t{1} << (c % 64); }
  Verdict refuse(Refusal why, std::string_view channel);
  bool acceptCounter(int sender, std::string_view channel, uint64_t counter, double steady_s, Refusal* why);
  int placeFor(double steady_s);  // a free sender place, or a forgotten sender's; -1 when none
  void forget(int sender);        // frees its place and its streams
  bool pinnedChannel(uint64_t channel_hash) const;

  std::optional<BusKey> key_;
  std::unique_ptr<SenderKeys> keys_;
  std::string program_;
  bool quiet_ = false;
  bool accept_replays_ = false;
  std::array<uint64_t, kMaxPinned> pinned_channels_{};
  int npinned_channels_ = 0;
  std::atomic<bool> have_pin_{false};
  SenderId pin_{};
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
