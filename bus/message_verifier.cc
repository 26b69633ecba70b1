#include "bus/message_verifier.h"

#include <openssl/crypto.h>

#include <chrono>
#include <cstdio>

#include "bus/printable_name.h"

namespace igms::bus {
namespace {

uint64_t fnv1a(std::string_view s) {
  uint64_t h = 1469598103934665603ull;
  for (char c : s) h = (h ^ static_cast<uint8_t>(c)) * 1099511628211ull;
  return h;
}

const char* advice(Refusal r) {
  switch (r) {
    case Refusal::kUnsigned:
      return "is unsigned: its sender has no bus key (start it with the same --key-file)";
    case Refusal::kBadSignature:
      return "fails its signature check: signed with another key (a different --key-file?) or forged";
    case Refusal::kReplayed:
      return "was seen before (a replay) or is older than the last 1024 from its sender";
    case Refusal::kTooManySenders:
      return "comes from one sender too many (more than 256 processes, or 2048 streams, heard within two minutes)";
    case Refusal::kStale:
      return "was signed more than a minute ago or ahead by this machine's clock (a replay, or clocks apart)";
    case Refusal::kReplayedSession:
      return "is replayed traffic (igms-replay play), which this program takes only with --accept-replay";
    case Refusal::kOtherSender:
      return "comes from another sender than the one this program joined (a second signer speaking for it)";
  }
  return "";
}

}  // namespace

struct MessageVerifier::Sender {
  SenderId id{};
  bool replayed = false;  // a replay's sender (its own key label)
  SenderMac mac;
  bool used = false;
  double heard = 0.0;  // steady clock, s: its newest accepted message
};

const char* refusalName(Refusal r) {
  static const char* names[kRefusals] = {"unsigned", "bad_signature",    "replayed",    "too_many_senders",
                                         "stale",    "replayed_session", "other_sender"};
  return names[static_cast<int>(r)];
}

int64_t VerifierCounts::refusedTotal() const {
  int64_t n = 0;
  for (int64_t r : refused) n += r;
  return n;
}

MessageVerifier::MessageVerifier(std::optional<BusKey> key, std::string program)
    : key_(std::move(key)), program_(std::move(program)) {
  if (!key_) return;
  keys_ = std::make_unique<SenderKeys>(*key_);
  senders_.reserve(kMaxSenders);
  for (int k = 0; k < kMaxSenders; ++k) senders_.push_back(std::make_unique<Sender>());
  scratch_ = std::make_unique<Sender>();
  streams_.resize(kMaxStreams);
}

MessageVerifier::~MessageVerifier() {
  if (key_) OPENSSL_cleanse(key_->data(), key_->size());
}

Verdict MessageVerifier::refuse(Refusal why, std::string_view channel) {
  refused_[static_cast<size_t>(why)].fetch_add(1, std::memory_order_relaxed);
  // One line per kind, the first time: what a person needs to fix a wrong or missing key.
  if (!quiet_ && !told_[static_cast<size_t>(why)].exchange(true)) {
    char name[kPrintableNameBytes];
    printableName(channel, name);
    std::fprintf(stderr, "%s: refused a message on %s: it %s (counted; later ones silently)\n", program_.c_str(), name,
                 advice(why));
  }
  Verdict v;
  v.why = why;
  return v;
}

bool MessageVerifier::acceptCounter(int sender, std::string_view channel, uint64_t counter, double steady_s,
                                    Refusal* why) {
  const uint64_t ch = fnv1a(channel);
  Stream* s = nullptr;
  Stream* free_place = nullptr;
  for (int k = 0; k < nstreams_ && !s; ++k) {
    Stream& x = streams_[static_cast<size_t>(k)];
    if (x.sender == sender && x.channel == ch) s = &x;
    else if (x.sender < 0 && !free_place) free_place = &x;  // a forgotten sender's
  }
  if (!s && !free_place && nstreams_ == kMaxStreams) {
    // The streams are full: the senders silent for kForgetS are forgotten, their streams freed.
    for (int k = 0; k < nsenders_; ++k) {
      const Sender& x = *senders_[static_cast<size_t>(k)];
      if (k != sender && x.used && steady_s - x.heard > kForgetS) forget(k);
    }
    for (int k = 0; k < nstreams_ && !free_place; ++k)
      if (streams_[static_cast<size_t>(k)].sender < 0) free_place = &streams_[static_cast<size_t>(k)];
  }
  if (!s) {
    if (!free_place && nstreams_ == kMaxStreams) {
      *why = Refusal::kTooManySenders;
      return false;
    }
    s = free_place ? free_place : &streams_[static_cast<size_t>(nstreams_++)];
    *s = Stream{sender, ch, counter, {}};
    setBit(*s, counter);
    return true;
  }
  if (counter > s->newest) {
    // The counters passed over leave the window's far end: their bits are cleared for reuse.
    if (counter - s->newest >= kWindow) {
      s->seen.fill(0);
    } else {
      for (uint64_t c = s->newest + 1; c < counter; ++c) s->seen[c % kWindow / 64] &= ~(uint64_t{1} << (c % 64));
    }
    s->newest = counter;
    setBit(*s, counter);
    return true;
  }
  if (s->newest - counter >= kWindow || seenBit(*s, counter)) {
    *why = Refusal::kReplayed;
    return false;
  }
  setBit(*s, counter);
  return true;
}

void MessageVerifier::forget(int sender) {
  senders_[static_cast<size_t>(sender)]->used = false;
  for (int k = 0; k < nstreams_; ++k)  // its streams go with it
    if (streams_[static_cast<size_t>(k)].sender == sender) streams_[static_cast<size_t>(k)].sender = -1;
}

int MessageVerifier::placeFor(double steady_s) {
  for (int k = 0; k < nsenders_; ++k)
    if (!senders_[static_cast<size_t>(k)]->used) return k;  // a forgotten sender's
  if (nsenders_ < kMaxSenders) return nsenders_++;
  int idle = -1;
  for (int k = 0; k < nsenders_; ++k) {
    const Sender& s = *senders_[static_cast<size_t>(k)];
    if (steady_s - s.heard > kForgetS && (idle < 0 || s.heard < senders_[static_cast<size_t>(idle)]->heard)) idle = k;
  }
  if (idle >= 0) forget(idle);
  return idle;
}

void MessageVerifier::pinSender(std::initializer_list<std::string_view> channels) {
  for (std::string_view c : channels)
    if (npinned_channels_ < kMaxPinned) pinned_channels_[static_cast<size_t>(npinned_channels_++)] = fnv1a(c);
}

bool MessageVerifier::pinnedChannel(uint64_t channel_hash) const {
  for (int k = 0; k < npinned_channels_; ++k)
    if (pinned_channels_[static_cast<size_t>(k)] == channel_hash) return true;
  return false;
}

std::optional<SenderId> MessageVerifier::pinned() const {
  if (!have_pin_.load(std::memory_order_acquire)) return std::nullopt;
  return pin_;
}

bool MessageVerifier::tagHolds(std::string_view channel, const uint8_t* data, size_t size) {
  Trailer t;
  if (!key_ || !findTrailer(data, size, &t)) return false;
  uint8_t tag[kTagBytes];
  return scratch_->mac.key(*keys_, t.sender, t.replayed) && scratch_->mac.compute(channel, data, size, t.counter, tag) &&
         CRYPTO_memcmp(tag, t.tag, kTagBytes) == 0;
}

Verdict MessageVerifier::check(std::string_view channel, const uint8_t* data, size_t size) {
  if (!key_) return checkAt(channel, data, size, 0, 0.0);
  return checkAt(channel, data, size, wallClockMicros(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
}

Verdict MessageVerifier::checkAt(std::string_view channel, const uint8_t* data, size_t size, int64_t now_us,
                                 double steady_s) {
  Trailer t;
  const bool has_trailer = findTrailer(data, size, &t);
  if (!key_) {
    if (has_trailer) {
      signed_unchecked_.fetch_add(1, std::memory_order_relaxed);
      if (!quiet_ && !told_[kRefusals].exchange(true)) {
        char name[kPrintableNameBytes];
        printableName(channel, name);
        std::fprintf(stderr,
                     "%s: messages on %s are signed but this program has no bus key: pass --key-file (or set %s); "
                     "taking them unchecked\n",
                     program_.c_str(), name, kKeyFileEnv);
      }
    }
    accepted_.fetch_add(1, std::memory_order_relaxed);
    return Verdict{true, Refusal::kUnsigned, has_trailer ? t.payload_bytes : size};
  }
  if (!has_trailer) return refuse(Refusal::kUnsigned, channel);
  int sender = -1;
  for (int k = 0; k < nsenders_ && sender < 0; ++k) {
    const Sender& x = *senders_[static_cast<size_t>(k)];
    if (x.used && x.id == t.sender && x.replayed == t.replayed) sender = k;
  }
  Sender* s = sender >= 0 ? senders_[static_cast<size_t>(sender)].get() : scratch_.get();
  if (sender < 0) {
    s->id = t.sender;
    s->replayed = t.replayed;
    if (!s->mac.key(*keys_, t.sender, t.replayed)) return refuse(Refusal::kBadSignature, channel);
  }
  uint8_t tag[kTagBytes];
  if (!s->mac.compute(channel, data, size, t.counter, tag) || CRYPTO_memcmp(tag, t.tag, kTagBytes) != 0)
    return refuse(Refusal::kBadSignature, channel);
  if (t.replayed && !accept_replays_) return refuse(Refusal::kReplayedSession, channel);
  const double age_s = 1e-6 * static_cast<double>(now_us - t.time_us);
  if (age_s > kMaxAgeS || age_s < -kMaxAgeS) return refuse(Refusal::kStale, channel);
  const bool pinning = npinned_channels_ > 0 && pinnedChannel(fnv1a(channel));
  if (pinning && have_pin_.load(std::memory_order_relaxed) && pin_ != t.sender)
    return refuse(Refusal::kOtherSender, channel);
  if (sender < 0) {
    // A new process with the key: it gets a place (the scratch context becomes its own).
    sender = placeFor(steady_s);
    if (sender < 0) return refuse(Refusal::kTooManySenders, channel);
    std::swap(senders_[static_cast<size_t>(sender)], scratch_);
    senders_[static_cast<size_t>(sender)]->used = true;
    scratch_->used = false;  // an evicted sender's context, free for the next new one
  }
  Refusal why;
  if (!acceptCounter(sender, channel, t.counter, steady_s, &why)) return refuse(why, channel);
  senders_[static_cast<size_t>(sender)]->heard = steady_s;
  if (pinning && !have_pin_.load(std::memory_order_relaxed)) {
    pin_ = t.sender;
    have_pin_.store(true, std::memory_order_release);
  }
  accepted_.fetch_add(1, std::memory_order_relaxed);
  Verdict v{true, Refusal::kUnsigned, t.payload_bytes};
  v.sender = t.sender;
  v.signed_us = t.time_us;
  v.replayed = t.replayed;
  return v;
}

VerifierCounts MessageVerifier::counts() const {
  VerifierCounts c;
  c.accepted = accepted_.load(std::memory_order_relaxed);
  c.signed_unchecked = signed_unchecked_.load(std::memory_order_relaxed);
  for (int k = 0; k < kRefusals; ++k) c.refused[static_cast<size_t>(k)] = refused_[static_cast<size_t>(k)].load();
  return c;
}

std::string MessageVerifier::summary() const {
  const VerifierCounts c = counts();
  std::string s = "accepted " + std::to_string(c.accepted) + ", refused " + std::to_string(c.refusedTotal());
  std::string reasons;
  for (int k = 0; k < kRefusals; ++k)
    if (c.refused[static_cast<size_t>(k)] > 0)
      reasons += std::string(reasons.empty() ? "" : ", ") + refusalName(static_cast<Refusal>(k)) + " " +
                 std::to_string(c.refused[static_cast<size_t>(k)]);
  if (!reasons.empty()) s += " (" + reasons + ")";
  if (!key_) s += c.signed_unchecked ? "; no bus key, " + std::to_string(c.signed_unchecked) + " signed taken unchecked"
                                     : "; no bus key";
  return s;
}

}  // namespace igms::bus
