// What a signed message looks like on the bus, and the MAC both ends compute.
//
//   payload (the LCM message, unchanged) | "IGB1" | sender (16) | counter (8) | time (8) | tag (16)
//   (counter and time big-endian; time: the sender's wall clock, microseconds since 1970)
//
// Replayed traffic (igms-replay play) is a sender of another kind: its magic
// is "IGR1" and its key is derived under its own label, so a replay can never
// pass for live traffic, and a live program takes it only when told to.
//
// The trailer sits after the payload, so a reader without the key decodes the
// message as before (LCM's decoders stop at the message's end). The tag is
// AES-256-GMAC (OpenSSL) over the channel's name, the payload and the trailer
// up to the tag, under a key of the sender's own: HMAC-SHA256(bus key,
// "igms bus v1" | sender). The sender is 16 random bytes a process draws at
// start, the counter goes up with every message it sends, and the GCM nonce is
// the counter: with a key per sender, no nonce is used twice. GMAC, not an HMAC,
// because it costs 1.4 us at the robot state's 5.2 kB where HMAC-SHA256 costs
// 6 us (bench/bus_signature_bench).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "bus/bus_key.h"

typedef struct evp_cipher_ctx_st EVP_CIPHER_CTX;
typedef struct evp_mac_ctx_st EVP_MAC_CTX;

namespace igms::bus {

using SenderId = std::array<uint8_t, 16>;

inline constexpr char kMagic[4] = {'I', 'G', 'B', '1'};
inline constexpr char kReplayMagic[4] = {'I', 'G', 'R', '1'};  // a replay's trailer (igms-replay play)
inline constexpr size_t kSenderBytes = 16, kCounterBytes = 8, kTimeBytes = 8, kTagBytes = 16;
inline constexpr size_t kTrailerBytes = sizeof kMagic + kSenderBytes + kCounterBytes + kTimeBytes + kTagBytes;  // 52

// The trailer of a message, when it has one (the magic at its place).
struct Trailer {
  SenderId sender{};
  uint64_t counter = 0;
  int64_t time_us = 0;  // when the sender signed it (its wall clock)
  const uint8_t* tag = nullptr;
  size_t payload_bytes = 0;
  bool replayed = false;  // a replay's trailer (kReplayMagic)
};
bool findTrailer(const uint8_t* data, size_t size, Trailer* out);

// The wall clock the trailer's time is in, microseconds since 1970.
int64_t wallClockMicros();

// A sender's key from the bus key: HMAC-SHA256(bus key, "igms bus v1" | sender),
// or under "igms bus replay v1" for a replay's sender.
// Keyed once, so each derivation costs 0.5 us, not the 2.9 us of a one-shot
// HMAC: a flood of forged senders is cheap to refuse.
class SenderKeys {
 public:
  explicit SenderKeys(const BusKey& bus_key);
  ~SenderKeys();
  SenderKeys(const SenderKeys&) = delete;
  SenderKeys& operator=(const SenderKeys&) = delete;
  bool derive(const SenderId& sender, bool replayed, uint8_t key[32]);

 private:
  EVP_MAC_CTX* ctx_;
};

// An AES-256-GCM context keyed for one sender.
class SenderMac {
 public:
  SenderMac();
  ~SenderMac();
  SenderMac(const SenderMac&) = delete;
  SenderMac& operator=(const SenderMac&) = delete;
  // False when OpenSSL fails (the context then refuses every tag).
  bool key(SenderKeys& keys, const SenderId& sender, bool replayed = false);
  // The tag of `data[0, size - kTagBytes)` (payload and trailer up to the tag) on `channel`.
  bool compute(std::string_view channel, const uint8_t* data, size_t size, uint64_t counter, uint8_t tag[kTagBytes]);

 private:
  EVP_CIPHER_CTX* ctx_;
};

}  // namespace igms::bus
