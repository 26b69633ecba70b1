// The bus key: 32 random bytes shared by the processes of one session, in a
// file only its owner may read (64 hex digits). The key signs every message
// (message_signer.h) and is never sent.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace igms::bus {

using BusKey = std::array<uint8_t, 32>;

// The command-line help every program shows for --key-file (env IGMS_KEY_FILE).
inline constexpr const char* kKeyFileHelp =
    "sign every message with the bus key in this file and accept only messages signed with it "
    "(default: $IGMS_KEY_FILE; without one, the bus is unauthenticated)";
inline constexpr const char* kKeyFileEnv = "IGMS_KEY_FILE";
// The help for --accept-replay, in the programs that act on what they hear (server, client, device).
inline constexpr const char* kAcceptReplayHelp =
    "also take replayed traffic (igms-replay play signs it as a replay; without this it is refused and counted "
    "as replayed_session)";

// Reads a key file. Throws std::runtime_error naming the file and the problem:
// missing, readable by group or others, not 64 hex digits.
BusKey loadBusKey(const std::string& path);

// The key a program runs with: none for an empty path. Prints one line to
// stderr when there is none: the bus is then unauthenticated.
std::optional<BusKey> busKeyFor(const std::string& program, const std::string& path);

// Writes a new random key to `path` (mode 0600, refusing to overwrite).
void createBusKeyFile(const std::string& path);

// Bytes as hex digits: the key's 64 for a key file (never for the bus or a log), a sender's for a status.
std::string hexOf(const uint8_t* bytes, size_t n);
inline std::string hexOf(const BusKey& key) { return hexOf(key.data(), key.size()); }

}  // namespace igms::bus
