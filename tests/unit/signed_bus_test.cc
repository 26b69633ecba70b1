// The signed bus's parts without a network: signatures hold, any change to a
// signed message breaks them, replays and other keys are refused, the window
// takes reordering, a reader without the key still decodes, key files are
// checked, and signing allocates nothing.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_signer.h"
#include "bus/message_verifier.h"
#include "igms/robot_state_t.hpp"
#include "safe_decode.h"
#include "tests/support/malloc_counter.h"

namespace igms::bus {
namespace {

BusKey keyOf(uint8_t seed) {
  BusKey k{};
  for (size_t i = 0; i < k.size(); ++i) k[i] = static_cast<uint8_t>(seed + 7 * i);
  return k;
}

std::vector<uint8_t> signedMessage(MessageSigner& signer, const std::string& channel, std::vector<uint8_t> payload) {
  const size_t n = payload.size();
  payload.resize(n + kTrailerBytes);
  payload.resize(signer.sign(channel, payload.data(), n));
  return payload;
}

Verdict check(MessageVerifier& v, const std::string& channel, const std::vector<uint8_t>& m) {
  return v.check(channel, m.data(), m.size());
}

TEST(SignedBus, ASignedMessageIsAcceptedOnceAndItsPayloadComesBack) {
  MessageSigner signer(keyOf(1));
  MessageVerifier v(keyOf(1), "test");
  const std::vector<uint8_t> payload = {1, 2, 3, 4, 5};
  const auto m = signedMessage(signer, "IGMS_ROBOT_STATE", payload);
  ASSERT_EQ(m.size(), payload.size() + 52);
  const Verdict first = check(v, "IGMS_ROBOT_STATE", m);
  EXPECT_TRUE(first.accepted);
  EXPECT_EQ(first.payload_bytes, payload.size());
  v.quiet();
  const Verdict again = check(v, "IGMS_ROBOT_STATE", m);
  EXPECT_FALSE(again.accepted);
  EXPECT_EQ(again.why, Refusal::kReplayed);
  EXPECT_EQ(v.counts().accepted, 1);
  EXPECT_EQ(v.counts().refused[static_cast<size_t>(Refusal::kReplayed)], 1);
}

// A forked child signs as a sender of its own: a new id and its counter from 1, so no (sender,
// counter) pair, a GMAC nonce under one subkey, is used by both processes. Its messages, signed by
// the signer it inherited, are accepted; the parent signs on as before.
TEST(SignedBus, AForkedChildSignsAsANewSenderNeverReusingANonce) {
  MessageSigner signer(keyOf(1));
  MessageVerifier v(keyOf(1), "test");
  const std::vector<uint8_t> payload = {9, 8, 7};
  const auto before = signedMessage(signer, "IGMS_COMMAND", payload);
  Trailer parent_before;
  ASSERT_TRUE(findTrailer(before.data(), before.size(), &parent_before));
  int pipe_fd[2];
  ASSERT_EQ(pipe(pipe_fd), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(pipe_fd[0]);
    const auto m = signedMessage(signer, "IGMS_COMMAND", payload);
    const bool all = write(pipe_fd[1], m.data(), m.size()) == static_cast<ssize_t>(m.size());
    _exit(all && signer.rekeyed() ? 0 : 1);
  }
  close(pipe_fd[1]);
  std::vector<uint8_t> from_child(before.size());
  size_t got = 0;
  for (ssize_t r; got < from_child.size() && (r = read(pipe_fd[0], from_child.data() + got, from_child.size() - got)) > 0;)
    got += static_cast<size_t>(r);
  close(pipe_fd[0]);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the child signed, having keyed itself for its own sender";
  ASSERT_EQ(got, before.size());
  const auto after = signedMessage(signer, "IGMS_COMMAND", payload);
  Trailer child_t, parent_after;
  ASSERT_TRUE(findTrailer(from_child.data(), from_child.size(), &child_t));
  ASSERT_TRUE(findTrailer(after.data(), after.size(), &parent_after));
  EXPECT_NE(child_t.sender, parent_before.sender) << "the child draws a sender of its own";
  EXPECT_EQ(child_t.counter, 1u) << "and counts from the start";
  EXPECT_EQ(parent_after.sender, parent_before.sender);
  EXPECT_EQ(parent_after.counter, parent_before.counter + 1);
  EXPECT_FALSE(child_t.sender == parent_after.sender && child_t.counter == parent_after.counter) << "a nonce twice";
  EXPECT_TRUE(check(v, "IGMS_COMMAND", before).accepted);
  EXPECT_TRUE(check(v, "IGMS_COMMAND", from_child).accepted) << "the child's tag holds under its own sender's key";
  EXPECT_TRUE(check(v, "IGMS_COMMAND", after).accepted);
}

TEST(SignedBus, EveryByteAndTheChannelAreCovered) {
  MessageSigner signer(keyOf(1));
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  const auto m = signedMessage(signer, "IGMS_COMMAND", std::vector<uint8_t>(100, 9));
  // Any flipped bit, in the payload or the trailer (but the magic, which makes it unsigned), is refused.
  for (size_t i = 0; i < m.size(); ++i) {
    auto bad = m;
    bad[i] ^= 0x10;
    const Verdict verdict = check(v, "IGMS_COMMAND", bad);
    EXPECT_FALSE(verdict.accepted) << "byte " << i;
    const bool magic = i >= 100 && i < 104;
    EXPECT_EQ(verdict.why, magic ? Refusal::kUnsigned : Refusal::kBadSignature) << "byte " << i;
  }
  // The same bytes on another channel.
  EXPECT_EQ(check(v, "IGMS_HAPTIC_INPUT", m).why, Refusal::kBadSignature);
  // Cut short, or with a byte added before the trailer.
  auto shorter = m;
  shorter.erase(shorter.begin());
  EXPECT_EQ(check(v, "IGMS_COMMAND", shorter).why, Refusal::kBadSignature);
  EXPECT_TRUE(check(v, "IGMS_COMMAND", m).accepted);
  EXPECT_EQ(v.counts().accepted, 1);
}

TEST(SignedBus, AnotherKeyAndNoSignatureAreRefused) {
  MessageSigner stranger(keyOf(2));
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  EXPECT_EQ(check(v, "IGMS_ROBOT_STATE", signedMessage(stranger, "IGMS_ROBOT_STATE", {1, 2, 3})).why,
            Refusal::kBadSignature);
  EXPECT_EQ(check(v, "IGMS_ROBOT_STATE", std::vector<uint8_t>(200, 1)).why, Refusal::kUnsigned);
  EXPECT_EQ(check(v, "IGMS_ROBOT_STATE", std::vector<uint8_t>{}).why, Refusal::kUnsigned);
  EXPECT_EQ(v.counts().refusedTotal(), 3);
}

TEST(SignedBus, TheWindowTakesReorderingButNotReplaysOrTheTooOld) {
  MessageSigner signer(keyOf(1));
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  constexpr size_t kW = MessageVerifier::kWindow;
  std::vector<std::vector<uint8_t>> m;
  for (size_t k = 0; k < 3 * kW; ++k) m.push_back(signedMessage(signer, "C", {static_cast<uint8_t>(k)}));
  // 10 first, then 5..9 late (reordered): all accepted once.
  EXPECT_TRUE(check(v, "C", m[10]).accepted);
  for (int k = 5; k < 10; ++k) EXPECT_TRUE(check(v, "C", m[static_cast<size_t>(k)]).accepted) << k;
  for (int k = 5; k <= 10; ++k) EXPECT_EQ(check(v, "C", m[static_cast<size_t>(k)]).why, Refusal::kReplayed) << k;
  // kW + 99, then 20 (older than the window), 100 (kW - 1 behind: new, taken once) and 10 again.
  EXPECT_TRUE(check(v, "C", m[kW + 99]).accepted);
  EXPECT_EQ(check(v, "C", m[20]).why, Refusal::kReplayed);
  EXPECT_TRUE(check(v, "C", m[100]).accepted);
  EXPECT_EQ(check(v, "C", m[100]).why, Refusal::kReplayed);
  EXPECT_EQ(check(v, "C", m[10]).why, Refusal::kReplayed);
  // A jump of more than the window: everything before it is too old, what follows it new.
  EXPECT_TRUE(check(v, "C", m[3 * kW - 1]).accepted);
  EXPECT_EQ(check(v, "C", m[kW + 99]).why, Refusal::kReplayed);
  EXPECT_TRUE(check(v, "C", m[2 * kW]).accepted);  // kW - 1 behind, never seen
  // Every counter once, in a shuffled order within the window: each accepted exactly once.
  MessageVerifier fresh(keyOf(1), "test");
  fresh.quiet();
  std::vector<size_t> order;
  for (size_t k = 0; k < kW; ++k) order.push_back(k);
  std::mt19937 rng(7);
  std::shuffle(order.begin() + 1, order.end(), rng);  // the first arrives first; the rest within kW of it
  size_t accepted = 0;
  for (size_t k : order) accepted += check(fresh, "C", m[k]).accepted;
  for (size_t k : order) accepted += check(fresh, "C", m[k]).accepted;
  EXPECT_EQ(accepted, kW);
  // Each channel has its own stream: a process's counter is shared by its channels.
  const auto other = signedMessage(signer, "D", {1});
  EXPECT_TRUE(check(v, "D", other).accepted);
  EXPECT_TRUE(check(v, "C", signedMessage(signer, "C", {1})).accepted);
}

TEST(SignedBus, AReaderWithoutTheKeyDecodesAsBefore) {
  robot_state_t s{};
  s.seq = 42;
  s.nq = 2;
  s.q = {0.5, -0.25};
  std::vector<uint8_t> bytes(static_cast<size_t>(s.getEncodedSize()));
  s.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  MessageSigner signer(keyOf(1));
  const auto m = signedMessage(signer, "IGMS_ROBOT_STATE", bytes);
  robot_state_t out;
  ASSERT_TRUE(safeDecode(m.data(), m.size(), &out));  // LCM stops at the message's end
  EXPECT_EQ(out.seq, 42);
  EXPECT_EQ(out.q[1], -0.25);
  MessageVerifier unkeyed(std::nullopt, "test");
  unkeyed.quiet();
  const Verdict verdict = check(unkeyed, "IGMS_ROBOT_STATE", m);
  EXPECT_TRUE(verdict.accepted);
  EXPECT_EQ(verdict.payload_bytes, bytes.size());
  EXPECT_EQ(unkeyed.counts().signed_unchecked, 1);
  EXPECT_TRUE(check(unkeyed, "IGMS_ROBOT_STATE", bytes).accepted);
  EXPECT_EQ(unkeyed.counts().signed_unchecked, 1);
}

// The trailer written out here from its description in message_signature.h, not by MessageSigner: a
// second reading of the format, and any sender, counter and time a test needs.
std::vector<uint8_t> signedAs(const BusKey& key, const SenderId& sender, uint64_t counter, int64_t time_us,
                              const std::string& channel, std::vector<uint8_t> payload) {
  auto put = [&](uint64_t v) {
    for (int i = 7; i >= 0; --i) payload.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  payload.insert(payload.end(), kMagic, kMagic + 4);
  payload.insert(payload.end(), sender.begin(), sender.end());
  put(counter);
  put(static_cast<uint64_t>(time_us));
  payload.resize(payload.size() + kTagBytes);
  SenderKeys keys(key);
  SenderMac mac;
  EXPECT_TRUE(mac.key(keys, sender));
  EXPECT_TRUE(mac.compute(channel, payload.data(), payload.size(), counter, payload.data() + payload.size() - kTagBytes));
  return payload;
}

SenderId senderOf(int k) {
  SenderId s{};
  s[0] = static_cast<uint8_t>(k);
  s[1] = static_cast<uint8_t>(k >> 8);
  return s;
}

TEST(SignedBus, AMessageSignedOverAMinuteAgoOrAheadIsStale) {
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  const int64_t now = wallClockMicros();
  const auto at = [&](int64_t t, uint64_t counter) {
    const auto m = signedAs(keyOf(1), senderOf(1), counter, t, "C", {1, 2});
    return v.checkAt("C", m.data(), m.size(), now, 100.0);
  };
  EXPECT_TRUE(at(now - 59'000'000, 1).accepted);
  EXPECT_EQ(at(now - 61'000'000, 2).why, Refusal::kStale);
  EXPECT_EQ(at(now + 61'000'000, 3).why, Refusal::kStale);
  EXPECT_TRUE(at(now + 1'000'000, 4).accepted);  // clocks a second apart: fine
}

TEST(SignedBus, ASenderSilentForAMinuteGivesItsPlaceToANewOne) {
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  const int64_t now = wallClockMicros();
  auto send = [&](int sender, uint64_t counter, double steady, const std::string& channel = "C") {
    const auto m = signedAs(keyOf(1), senderOf(sender), counter, now, channel, {7});
    return v.checkAt(channel, m.data(), m.size(), now, steady);
  };
  // A full table: every sender heard at t = 0 (two channels each).
  for (int k = 0; k < MessageVerifier::kMaxSenders; ++k) {
    ASSERT_TRUE(send(k, 1, 0.0).accepted) << k;
    ASSERT_TRUE(send(k, 2, 0.0, "D").accepted) << k;
  }
  // Within the minute, a new sender has no place.
  EXPECT_EQ(send(1000, 1, 30.0).why, Refusal::kTooManySenders);
  // Sender 5 speaks at 30 s; at 70 s the others have been silent over a minute: a new one takes an idle place.
  EXPECT_TRUE(send(5, 3, 30.0).accepted);
  EXPECT_TRUE(send(1000, 1, 70.0).accepted);
  EXPECT_TRUE(send(5, 4, 70.0).accepted);  // 5 kept its place and its window
  EXPECT_EQ(send(5, 3, 70.0).why, Refusal::kReplayed);
  // Restarted programs (a new sender each) never run out of places once the old ones are silent.
  for (int k = 2000; k < 2000 + 3 * MessageVerifier::kMaxSenders; ++k)
    ASSERT_TRUE(send(k, 1, 200.0 + 100.0 * (k - 2000)).accepted) << k;
  EXPECT_EQ(v.counts().refused[static_cast<size_t>(Refusal::kTooManySenders)], 1);
}

TEST(SignedBus, ForgedSenderIdsNeverTakeAPlace) {
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  for (int k = 0; k < 500; ++k) {
    std::vector<uint8_t> junk(60, static_cast<uint8_t>(k));
    std::memcpy(junk.data() + junk.size() - kTrailerBytes, kMagic, 4);  // a trailer's shape, random sender and tag
    EXPECT_EQ(check(v, "C", junk).why, Refusal::kBadSignature);
  }
  MessageSigner signer(keyOf(1));
  EXPECT_TRUE(check(v, "C", signedMessage(signer, "C", {1})).accepted);
}

TEST(SignedBus, SigningAndCheckingAllocateNothing) {
  MessageSigner signer(keyOf(1));
  MessageVerifier v(keyOf(1), "test");
  std::vector<uint8_t> buffer(5200 + kTrailerBytes, 3);
  // The format as written out independently (signedAs) checks as MessageSigner's does.
  const auto independent = signedAs(keyOf(1), senderOf(77), 1, wallClockMicros(), "IGMS_ROBOT_STATE", {1, 2, 3});
  ASSERT_TRUE(v.check("IGMS_ROBOT_STATE", independent.data(), independent.size()).accepted);
  size_t n = signer.sign("IGMS_ROBOT_STATE", buffer.data(), 5200);
  ASSERT_TRUE(v.check("IGMS_ROBOT_STATE", buffer.data(), n).accepted);  // the sender's place is taken here
  bool all = true;
  const size_t allocations = test::allocationsDuring([&] {
    for (int k = 0; k < 100; ++k) {
      n = signer.sign("IGMS_ROBOT_STATE", buffer.data(), 5200);
      all = all && v.check("IGMS_ROBOT_STATE", buffer.data(), n).accepted;
    }
  });
  EXPECT_TRUE(all);
  EXPECT_EQ(allocations, 0u);
}

class KeyFile : public ::testing::Test {
 protected:
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("igms_key_" + std::to_string(getpid()));
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text, mode_t mode) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << text;
    chmod(path.c_str(), mode);
    return path;
  }
  static std::string errorOf(const std::string& path) {
    try {
      loadBusKey(path);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(KeyFile, ACreatedKeyLoadsAndIsPrivate) {
  const std::string path = (dir / "bus.key").string();
  createBusKeyFile(path);
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const BusKey k = loadBusKey(path);
  std::ifstream in(path);
  std::string text;
  in >> text;
  EXPECT_EQ(hexOf(k), text);
  EXPECT_THROW(createBusKeyFile(path), std::runtime_error);  // never overwritten
  createBusKeyFile((dir / "other.key").string());
  EXPECT_NE(hexOf(loadBusKey((dir / "other.key").string())), text);
}

TEST_F(KeyFile, BadFilesNameTheFileAndTheProblem) {
  const std::string hex(64, 'a');
  EXPECT_NE(errorOf((dir / "none.key").string()).find("none.key: No such file"), std::string::npos);
  EXPECT_NE(errorOf(write("open.key", hex, 0644)).find("open.key: readable by others (mode 644); chmod 600 it"),
            std::string::npos);
  EXPECT_NE(errorOf(write("short.key", "abcd", 0600)).find("short.key: holds 4 characters, not the key's 64"),
            std::string::npos);
  EXPECT_NE(errorOf(write("nothex.key", "g" + hex.substr(1), 0600)).find("nothex.key: not hex at character 1"),
            std::string::npos);
  EXPECT_EQ(errorOf(write("good.key", hex + "\n", 0600)), "");
  // A link to a good key is refused (a link can be swapped between a check and a read), and so is a
  // key another user owns; the file that is read is the one that was checked.
  std::filesystem::create_symlink(dir / "good.key", dir / "link.key");
  EXPECT_NE(errorOf((dir / "link.key").string()).find("link.key: a symbolic link; give the key file itself"),
            std::string::npos);
  const std::string theirs = write("theirs.key", hex + "\n", 0600);
  if (geteuid() == 0) {  // only root can give a file away
    ASSERT_EQ(chown(theirs.c_str(), 65534, 65534), 0);
    EXPECT_NE(errorOf(theirs).find("theirs.key: owned by uid 65534, not by this user (uid 0)"), std::string::npos);
  } else {
    const std::string unreadable = write("unreadable.key", hex + "\n", 0200);
    EXPECT_NE(errorOf(unreadable).find("unreadable.key: not readable by this user (permission denied)"),
              std::string::npos);
  }
  EXPECT_NE(errorOf(dir.string()).find("not a regular file"), std::string::npos);
}

}  // namespace
}  // namespace igms::bus
