#include "bus/message_signature.h"

#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>

#include <chrono>
#include <cstring>
#include <stdexcept>

namespace igms::bus {

bool findTrailer(const uint8_t* data, size_t size, Trailer* out) {
  if (size < kTrailerBytes) return false;
  const uint8_t* t = data + size - kTrailerBytes;
  const bool live = std::memcmp(t, kMagic, sizeof kMagic) == 0;
  if (!live && std::memcmp(t, kReplayMagic, sizeof kReplayMagic) != 0) return false;
  out->replayed = !live;
  t += sizeof kMagic;
  std::memcpy(out->sender.data(), t, kSenderBytes);
  t += kSenderBytes;
  uint64_t c = 0;
  for (size_t i = 0; i < kCounterBytes; ++i) c = c << 8 | t[i];
  out->counter = c;
  t += kCounterBytes;
  uint64_t time = 0;
  for (size_t i = 0; i < kTimeBytes; ++i) time = time << 8 | t[i];
  out->time_us = static_cast<int64_t>(time);
  out->tag = t + kTimeBytes;
  out->payload_bytes = size - kTrailerBytes;
  return true;
}

int64_t wallClockMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

SenderMac::SenderMac() : ctx_(EVP_CIPHER_CTX_new()) {
  if (!ctx_ || EVP_EncryptInit_ex(ctx_, EVP_aes_256_gcm(), nullptr, nullptr, nullptr) != 1)
    throw std::runtime_error("OpenSSL: no AES-256-GCM context");
}

SenderMac::~SenderMac() { EVP_CIPHER_CTX_free(ctx_); }

SenderKeys::SenderKeys(const BusKey& bus_key) {
  EVP_MAC* mac = EVP_MAC_fetch(nullptr, "HMAC", nullptr);
  ctx_ = mac ? EVP_MAC_CTX_new(mac) : nullptr;
  EVP_MAC_free(mac);  // the context holds its own reference
  char digest[] = "SHA256";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string(OSSL_MAC_PARAM_DIGEST, digest, 0),
                               OSSL_PARAM_construct_end()};
  if (!ctx_ || EVP_MAC_init(ctx_, bus_key.data(), bus_key.size(), params) != 1)
    throw std::runtime_error("OpenSSL: no HMAC-SHA256");
}

SenderKeys::~SenderKeys() { EVP_MAC_CTX_free(ctx_); }

bool SenderKeys::derive(const SenderId& sender, bool replayed, uint8_t key[32]) {
  static constexpr std::string_view kLive = "igms bus v1", kReplay = "igms bus replay v1";
  const std::string_view label = replayed ? kReplay : kLive;
  size_t length = 0;
  // A null key restarts the MAC under the key it was initialised with.
  return EVP_MAC_init(ctx_, nullptr, 0, nullptr) == 1 &&
         EVP_MAC_update(ctx_, reinterpret_cast<const uint8_t*>(label.data()), label.size()) == 1 &&
         EVP_MAC_update(ctx_, sender.data(), sender.size()) == 1 && EVP_MAC_final(ctx_, key, &length, 32) == 1 &&
         length == 32;
}

bool SenderMac::key(SenderKeys& keys, const SenderId& sender, bool replayed) {
  uint8_t subkey[32];
  const bool ok = keys.derive(sender, replayed, subkey) && EVP_EncryptInit_ex(ctx_, nullptr, nullptr, subkey, nullptr) == 1;
  OPENSSL_cleanse(subkey, sizeof subkey);
  return ok;
}

bool SenderMac::compute(std::string_view channel, const uint8_t* data, size_t size, uint64_t counter,
                        uint8_t tag[kTagBytes]) {
  uint8_t nonce[12] = {0};
  for (int i = 0; i < 8; ++i) nonce[11 - i] = static_cast<uint8_t>(counter >> (8 * i));
  const uint8_t length[4] = {static_cast<uint8_t>(channel.size() >> 24), static_cast<uint8_t>(channel.size() >> 16),
                             static_cast<uint8_t>(channel.size() >> 8), static_cast<uint8_t>(channel.size())};
  int out = 0;
  // GMAC: GCM with everything as associated data and nothing to encrypt.
  return EVP_EncryptInit_ex(ctx_, nullptr, nullptr, nullptr, nonce) == 1 &&
         EVP_EncryptUpdate(ctx_, nullptr, &out, length, sizeof length) == 1 &&
         EVP_EncryptUpdate(ctx_, nullptr, &out, reinterpret_cast<const uint8_t*>(channel.data()),
                           static_cast<int>(channel.size())) == 1 &&
         EVP_EncryptUpdate(ctx_, nullptr, &out, data, static_cast<int>(size - kTagBytes)) == 1 &&
         EVP_EncryptFinal_ex(ctx_, tag, &out) == 1 &&
         EVP_CIPHER_CTX_ctrl(ctx_, EVP_CTRL_GCM_GET_TAG, static_cast<int>(kTagBytes), tag) == 1;
}

}  // namespace igms::bus
