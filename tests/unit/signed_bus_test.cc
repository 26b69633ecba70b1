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
#include "bus/printable_name.h"
#include "igms/robot_state_t.hpp"
#include "safe_decode.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/signed_message.h"
#include "tests/support/signed_as.h"

namespace igms::bus {
namespace {

using test::keyOf;
using test::signedMessage;

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
  // 'B' ^ 0x10 is 'R': the magic of a replay, whose key is another, so its tag fails.
  for (size_t i = 0; i < m.size(); ++i) {
    auto bad = m;
    bad[i] ^= 0x10;
    const Verdict verdict = check(v, "IGMS_COMMAND", bad);
    EXPECT_FALSE(verdict.accepted) << "byte " << i;
    const bool magic = i >= 100 && i < 104 && i != 102;
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

using test::senderOf;
using test::signedAs;

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

TEST(SignedBus, ASenderSilentForTwoMinutesGivesItsPlaceToANewOne) {
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
  // Within the two minutes, a new sender has no place.
  EXPECT_EQ(send(1000, 1, 30.0).why, Refusal::kTooManySenders);
  EXPECT_EQ(send(1001, 1, 110.0).why, Refusal::kTooManySenders);
  // Sender 5 speaks at 30 s; at 130 s the others have been silent over two minutes: a new one takes an idle place.
  EXPECT_TRUE(send(5, 3, 30.0).accepted);
  EXPECT_TRUE(send(1000, 1, 130.0).accepted);
  EXPECT_TRUE(send(5, 4, 130.0).accepted);  // 5 kept its place and its window
  EXPECT_EQ(send(5, 3, 130.0).why, Refusal::kReplayed);
  // Restarted programs (a new sender each) never run out of places once the old ones are silent.
  for (int k = 2000; k < 2000 + 3 * MessageVerifier::kMaxSenders; ++k)
    ASSERT_TRUE(send(k, 1, 300.0 + 150.0 * (k - 2000)).accepted) << k;
  EXPECT_EQ(v.counts().refused[static_cast<size_t>(Refusal::kTooManySenders)], 2);
}

// Issue 44, item 3: freshness is judged on the sender's clock, silence on the receiver's. A sender
// whose clock runs 30 s ahead signs a message that stays fresh here for 90 s; forgotten after a
// minute of silence (as it was), its captured message came back as a new sender's first. A sender is
// now forgotten only after twice the freshness window, when nothing it signed can be fresh.
TEST(SignedBus, ASenderWhoseClockRunsAheadCannotBeReplayedOnceForgotten) {
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  const int64_t now = wallClockMicros();
  const int64_t ahead = 30'000'000;
  const auto captured = signedAs(keyOf(1), senderOf(9999), 1, now + ahead, "C", {4, 2});
  ASSERT_TRUE(v.checkAt("C", captured.data(), captured.size(), now, 0.0).accepted);
  // Others fill the table and keep speaking; the ahead sender is silent.
  for (double t : {0.0, 50.0, 61.0, 85.0}) {
    for (int k = 0; k < MessageVerifier::kMaxSenders - 1; ++k) {
      const auto m = signedAs(keyOf(1), senderOf(k), 1 + static_cast<uint64_t>(t), now + static_cast<int64_t>(t * 1e6),
                              "C", {1});
      v.checkAt("C", m.data(), m.size(), now + static_cast<int64_t>(t * 1e6), t);
    }
    // A newcomer asks for a place: the silent sender is the one that could be forgotten.
    const auto newcomer = signedAs(keyOf(1), senderOf(20000 + static_cast<int>(t)), 1,
                                   now + static_cast<int64_t>(t * 1e6), "C", {1});
    v.checkAt("C", newcomer.data(), newcomer.size(), now + static_cast<int64_t>(t * 1e6), t);
    // The capture, replayed: it is still fresh by the clocks (signed 30 s ahead) until 90 s.
    const Verdict replay = v.checkAt("C", captured.data(), captured.size(), now + static_cast<int64_t>(t * 1e6), t);
    EXPECT_FALSE(replay.accepted) << "replayed at " << t << " s";
  }
  EXPECT_EQ(v.counts().accepted, 1 + 4 * (MessageVerifier::kMaxSenders - 1));
}

// Issue 44, item 7: the streams of senders gone silent are reclaimed. 160 runs of igms-replay (a new
// sender each, 13 channels) fill the 2048 streams while the sender table (256) never does; before,
// every later sender was refused for good.
TEST(SignedBus, StreamsOfSilentSendersAreReclaimed) {
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  const int64_t now = wallClockMicros();
  for (int run = 0; run < 200; ++run) {
    const double t = 10.0 * run;  // a run every 10 s: the older ones silent for minutes
    for (int c = 0; c < 13; ++c) {
      const std::string channel = "IGMS_CHANNEL_" + std::to_string(c);
      const auto m = signedAs(keyOf(1), senderOf(run), 1, now + static_cast<int64_t>(t * 1e6), channel, {1});
      ASSERT_TRUE(v.checkAt(channel, m.data(), m.size(), now + static_cast<int64_t>(t * 1e6), t).accepted)
          << "run " << run << ", channel " << c;
    }
  }
  EXPECT_EQ(v.counts().refused[static_cast<size_t>(Refusal::kTooManySenders)], 0);
}

// Issue 44, item 1: replayed traffic is a sender of its own kind. It is refused (counted) unless the
// program takes replays; its tag never passes as live traffic's (another key label); a log's recorded
// message can be checked for its tag alone, whatever its age.
TEST(SignedBus, AReplaysSignatureIsRefusedUnlessReplaysAreTaken) {
  MessageSigner replayer(keyOf(1), SenderKind::kReplay);
  const auto m = signedMessage(replayer, "IGMS_COMMAND", {1, 2, 3});
  Trailer t;
  ASSERT_TRUE(findTrailer(m.data(), m.size(), &t));
  EXPECT_TRUE(t.replayed);
  MessageVerifier live(keyOf(1), "test");
  live.quiet();
  const Verdict refused = check(live, "IGMS_COMMAND", m);
  EXPECT_FALSE(refused.accepted);
  EXPECT_EQ(refused.why, Refusal::kReplayedSession);
  EXPECT_EQ(live.counts().refused[static_cast<size_t>(Refusal::kReplayedSession)], 1);
  MessageVerifier watcher(keyOf(1), "test");
  watcher.acceptReplays();
  const Verdict taken = check(watcher, "IGMS_COMMAND", m);
  EXPECT_TRUE(taken.accepted);
  EXPECT_TRUE(taken.replayed);
  // The replay's trailer made to look live: its tag is under the replay label, so it fails.
  auto relabelled = m;
  std::memcpy(relabelled.data() + relabelled.size() - kTrailerBytes, kMagic, 4);
  live.quiet();
  EXPECT_EQ(check(live, "IGMS_COMMAND", relabelled).why, Refusal::kBadSignature);
  // The same sender id signing live and as a replay are two senders: a live message of it is taken.
  EXPECT_TRUE(check(live, "IGMS_COMMAND", signedAs(keyOf(1), t.sender, 1, wallClockMicros(), "IGMS_COMMAND", {5})).accepted);
  // Tags of recorded messages: an hour old still holds; another key's or an altered one does not.
  const auto old = signedAs(keyOf(1), senderOf(3), 7, wallClockMicros() - 3'600'000'000LL, "IGMS_ROBOT_STATE", {9});
  MessageVerifier recorded(keyOf(1), "test");
  EXPECT_TRUE(recorded.tagHolds("IGMS_ROBOT_STATE", old.data(), old.size()));
  EXPECT_TRUE(recorded.tagHolds("IGMS_COMMAND", m.data(), m.size()));
  EXPECT_FALSE(recorded.tagHolds("IGMS_COMMAND", relabelled.data(), relabelled.size()));
  EXPECT_FALSE(recorded.tagHolds("IGMS_ROBOT_STATE_2", old.data(), old.size()));
  const auto other = signedAs(keyOf(2), senderOf(3), 7, wallClockMicros(), "IGMS_ROBOT_STATE", {9});
  EXPECT_FALSE(recorded.tagHolds("IGMS_ROBOT_STATE", other.data(), other.size()));
  EXPECT_EQ(recorded.counts().accepted, 0);  // checking a tag takes nothing
}

// Issue 44, item 1: a client pins its server, a bus device its device: the first sender accepted on
// the pinned channels is the only one taken on them; another key holder speaking for it is refused.
TEST(SignedBus, APinnedChannelTakesOnlyTheFirstSender) {
  MessageVerifier v(keyOf(1), "test");
  v.quiet();
  v.pinSender({"IGMS_ROBOT_STATE", "IGMS_SERVER_STATUS"});
  EXPECT_FALSE(v.pinned().has_value());
  const int64_t now = wallClockMicros();
  auto send = [&](int sender, uint64_t counter, const std::string& channel) {
    const auto m = signedAs(keyOf(1), senderOf(sender), counter, now, channel, {1});
    return v.checkAt(channel, m.data(), m.size(), now, 1.0);
  };
  EXPECT_TRUE(send(1, 1, "IGMS_SERVER_STATUS").accepted);
  ASSERT_TRUE(v.pinned().has_value());
  EXPECT_EQ(*v.pinned(), senderOf(1));
  EXPECT_TRUE(send(1, 2, "IGMS_ROBOT_STATE").accepted);
  EXPECT_EQ(send(2, 1, "IGMS_ROBOT_STATE").why, Refusal::kOtherSender);
  EXPECT_EQ(send(2, 2, "IGMS_SERVER_STATUS").why, Refusal::kOtherSender);
  EXPECT_TRUE(send(2, 3, "IGMS_BUS_STATUS").accepted);  // not pinned
  EXPECT_TRUE(send(1, 3, "IGMS_ROBOT_STATE").accepted);
  EXPECT_EQ(v.counts().refused[static_cast<size_t>(Refusal::kOtherSender)], 2);
}

// Issue 44, item 7: names from the wire reach a terminal escaped: no escape sequence, no newline.
TEST(SignedBus, NamesFromTheWireArePrintable) {
  EXPECT_EQ(printableName("IGMS_ROBOT_STATE"), "IGMS_ROBOT_STATE");
  EXPECT_EQ(printableName(std::string("A\x1b[2J\nB\\", 8)), "A\\x1b[2J\\x0aB\\x5c");
  const std::string long_name(500, 'x');
  EXPECT_EQ(printableName(long_name), std::string(kPrintableNameChars, 'x') + "...");
  char buffer[kPrintableNameBytes];
  printableName(std::string(500, '\x07'), buffer);  // the worst case fits its buffer
  EXPECT_EQ(std::strlen(buffer), 4 * kPrintableNameChars + 3);
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
  const size_t allocations = igms::test::allocationsDuring([&] {
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
