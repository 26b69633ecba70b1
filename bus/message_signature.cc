#include "bus/message_signature.h"

#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <cstring>
#include <stdexcept>

namespace igms::bus {

bool findTrailer(const uint8_t* data, size_t size, Trailer* out) {
  if (size < kTrailerBytes) return false;
  const uint8_t* t = data + size - kTrailerBytes;
  if (std::memcmp(t, kMagic, sizeof kMagic) != 0) return false;
  t += sizeof kMagic;
  std::memcpy(out->sender.data(), t, kSenderBytes);
  t += kSenderBytes;
  uint64_t c = 0;
  for (size_t i = 0; i < kCounterBytes; ++i) c = c << 8 | t[i];
  out->counter = c;
  out->tag = t + kCounterBytes;
  out->payload_bytes = size - kTrailerBytes;
  return true;
}

SenderMac::SenderMac() : ctx_(EVP_CIPHER_CTX_new()) {
  if (!ctx_ || EVP_EncryptInit_ex(ctx_, EVP_aes_256_gcm(), nullptr, nullptr, nullptr) != 1)
    throw std::runtime_error("OpenSSL: no AES-256-GCM context");
}

SenderMac::~SenderMac() { EVP_CIPHER_CTX_free(ctx_); }

void SenderMac::key(const BusKey& bus_key, const SenderId& sender) {
  static constexpr char kLabel[] = "igms bus v1";
  uint8_t input[sizeof kLabel - 1 + kSenderBytes];
  std::memcpy(input, kLabel, sizeof kLabel - 1);
  std::memcpy(input + sizeof kLabel - 1, sender.data(), kSenderBytes);
  uint8_t subkey[32];
  unsigned length = 0;
  if (!HMAC(EVP_sha256(), bus_key.data(), static_cast<int>(bus_key.size()), input, sizeof input, subkey, &length) ||
      EVP_EncryptInit_ex(ctx_, nullptr, nullptr, subkey, nullptr) != 1)
    throw std::runtime_error("OpenSSL: cannot key AES-256-GCM");
  OPENSSL_cleanse(subkey, sizeof subkey);
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
