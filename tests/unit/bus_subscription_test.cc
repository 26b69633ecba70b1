// bus::subscribe and bus::subscribeRaw, the one receive path every program uses: a handler sees
// only what the verifier accepted and (typed) what decoded; refusals and undecodable messages are
// counted and reach no handler; a filter keeps unwanted channels from being checked at all; a
// destroyed subscription hears nothing more. (memq://: LCM in process, no socket.)
#include <gtest/gtest.h>

#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "bus/message_signer.h"
#include "bus/message_verifier.h"
#include "bus/subscription.h"
#include "igms/robot_state_t.hpp"
#include "tests/support/signed_message.h"

namespace igms::bus {
namespace {

using test::keyOf;
using test::signedMessage;

std::vector<uint8_t> encoded(const robot_state_t& m) {
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return bytes;
}

robot_state_t stateNumbered(int64_t seq) {
  robot_state_t m{};
  m.seq = seq;
  m.sim_time = 0.001 * static_cast<double>(seq);
  m.nq = m.nv = 2;
  m.q = {0.5, -0.25};
  m.v = {1.0, 2.0};
  m.qdd = {0.0, 0.0};
  m.tau = {0.0, 0.0};  // nhands = nlinks = 0: their arrays are empty
  return m;
}

struct Bus {
  lcm::LCM lcm{"memq://"};
  void send(const std::string& channel, const std::vector<uint8_t>& bytes) {
    ASSERT_EQ(lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size())), 0);
    ASSERT_GT(lcm.handleTimeout(1000), 0);
  }
};

TEST(BusSubscription, OnlyAcceptedMessagesThatDecodeReachTheHandler) {
  Bus bus;
  ASSERT_TRUE(bus.lcm.good());
  MessageSigner signer(keyOf(1));
  MessageVerifier verifier(keyOf(1), "bus_subscription_test");
  verifier.quiet();
  std::vector<int64_t> heard;
  int undecodable_told = 0;
  auto sub = subscribe<robot_state_t>(
      bus.lcm, verifier, "IGMS_ROBOT_STATE",
      [&](const robot_state_t& m, const Verdict& v) {
        EXPECT_TRUE(v.accepted);
        EXPECT_EQ(m.q, (std::vector<double>{0.5, -0.25}));
        heard.push_back(m.seq);
      },
      0, [&](const Verdict& v) {
        EXPECT_TRUE(v.accepted);
        ++undecodable_told;
      });
  ASSERT_TRUE(sub->good());

  const auto first = signedMessage(signer, "IGMS_ROBOT_STATE", encoded(stateNumbered(7)));
  bus.send("IGMS_ROBOT_STATE", first);
  bus.send("IGMS_ROBOT_STATE", first);                        // replayed: refused by the verifier
  bus.send("IGMS_ROBOT_STATE", encoded(stateNumbered(8)));    // unsigned: refused
  MessageSigner other(keyOf(2));
  bus.send("IGMS_ROBOT_STATE", signedMessage(other, "IGMS_ROBOT_STATE", encoded(stateNumbered(9))));  // another key
  // Signed, but not a robot_state_t: a wrong fingerprint, then a state cut short.
  bus.send("IGMS_ROBOT_STATE", signedMessage(signer, "IGMS_ROBOT_STATE", std::vector<uint8_t>(40, 0xab)));
  auto cut = encoded(stateNumbered(10));
  cut.resize(cut.size() - 9);
  bus.send("IGMS_ROBOT_STATE", signedMessage(signer, "IGMS_ROBOT_STATE", cut));
  auto header = encoded(stateNumbered(11));
  header.resize(12);  // the fingerprint and half a field
  bus.send("IGMS_ROBOT_STATE", signedMessage(signer, "IGMS_ROBOT_STATE", header));
  bus.send("IGMS_ROBOT_STATE", signedMessage(signer, "IGMS_ROBOT_STATE", encoded(stateNumbered(12))));

  EXPECT_EQ(heard, (std::vector<int64_t>{7, 12}));
  EXPECT_EQ(sub->undecodable(), 3);
  EXPECT_EQ(undecodable_told, 3);
  const VerifierCounts c = verifier.counts();
  EXPECT_EQ(c.accepted, 5);  // the two states and the three that did not decode
  EXPECT_EQ(c.refused[static_cast<size_t>(Refusal::kReplayed)], 1);
  EXPECT_EQ(c.refused[static_cast<size_t>(Refusal::kUnsigned)], 1);
  EXPECT_EQ(c.refused[static_cast<size_t>(Refusal::kBadSignature)], 1);
}

TEST(BusSubscription, ARawSubscriptionSeesTheWholeMessageItsRefusalsWhenAskedAndOnlyWantedChannels) {
  Bus bus;
  MessageSigner signer(keyOf(3));
  MessageVerifier verifier(keyOf(3), "bus_subscription_test");
  verifier.quiet();
  struct Seen {
    std::string channel;
    size_t size, payload;
    bool accepted;
  };
  std::vector<Seen> seen;
  auto take = [&](const std::string& channel, const lcm::ReceiveBuffer& m, const Verdict& v) {
    seen.push_back({channel, m.data_size, v.payload_bytes, v.accepted});
  };
  RawOptions o;
  o.refused = take;
  o.wanted = [](const std::string& channel) { return channel != "SKIPPED"; };
  auto sub = subscribeRaw(bus.lcm, verifier, ".*", take, o);
  const std::vector<uint8_t> payload(30, 1);
  const auto good = signedMessage(signer, "A", payload);
  bus.send("A", good);
  bus.send("A", payload);  // unsigned
  bus.send("SKIPPED", payload);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].channel, "A");
  EXPECT_TRUE(seen[0].accepted);
  EXPECT_EQ(seen[0].size, good.size());  // with its trailer: a logger records it, a relay forwards it
  EXPECT_EQ(seen[0].payload, payload.size());
  EXPECT_FALSE(seen[1].accepted);
  EXPECT_EQ(seen[1].size, payload.size());
  const VerifierCounts c = verifier.counts();
  EXPECT_EQ(c.accepted + c.refusedTotal(), 2);  // the unwanted channel was never checked

  // Without `refused`, a refusal reaches no one (and is still counted).
  seen.clear();
  auto quiet = subscribeRaw(bus.lcm, verifier, "B", take);
  sub.reset();  // a destroyed subscription hears nothing more
  bus.send("B", payload);
  bus.send("B", signedMessage(signer, "B", payload));
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_TRUE(seen[0].accepted);
  EXPECT_EQ(verifier.counts().refusedTotal(), 2);
}

}  // namespace
}  // namespace igms::bus
