// bus/message_verifier against the shared signed-bus vectors (tests/data/bus_vectors.json), which
// python/igmsbus.py passes too (tests/unit/igmsbus_vectors_test.py): the same exact signatures, and
// the same verdict at every step of every sequence.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bus/message_signature.h"
#include "bus/message_verifier.h"
#include "tests/support/signed_as.h"

namespace igms::bus {
namespace {

std::vector<uint8_t> fromHex(const std::string& hex) {
  std::vector<uint8_t> out;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) out.push_back(static_cast<uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return out;
}

BusKey keyFrom(const std::string& hex) {
  BusKey k{};
  const auto b = fromHex(hex);
  std::copy(b.begin(), b.end(), k.begin());
  return k;
}

using test::senderOf;

nlohmann::json vectors() {
  std::ifstream in(std::string(IGMS_SOURCE_DIR) + "/tests/data/bus_vectors.json");
  return nlohmann::json::parse(in);
}

TEST(BusVectors, TheExactSignatures) {
  const nlohmann::json doc = vectors();
  const BusKey key = keyFrom(doc["key"]);
  ASSERT_GE(doc["signatures"].size(), 4u);
  for (const auto& v : doc["signatures"]) {
    SenderId sender{};
    const auto s = fromHex(v["sender"]);
    std::copy(s.begin(), s.end(), sender.begin());
    const auto m = test::signedAs(key, sender, v["counter"], v["time_us"], v["channel"], fromHex(v["payload"]), v["replayed"]);
    EXPECT_EQ(m, fromHex(v["message"])) << v["channel"];
    MessageVerifier verifier(key, "test");
    verifier.acceptReplays();
    const Verdict taken = verifier.checkAt(v["channel"].get<std::string>(), m.data(), m.size(), v["time_us"], 0.0);
    EXPECT_TRUE(taken.accepted);
    EXPECT_EQ(taken.payload_bytes, fromHex(v["payload"]).size());
  }
}

TEST(BusVectors, EverySequenceStepByStep) {
  const nlohmann::json doc = vectors();
  const BusKey key = keyFrom(doc["key"]), other = keyFrom(doc["other_key"]);
  const int64_t base = doc["base_us"];
  int steps = 0;
  for (const auto& seq : doc["sequences"]) {
    MessageVerifier verifier(key, "test");
    verifier.quiet();
    if (seq.value("accept_replays", false)) verifier.acceptReplays();
    int i = 0;
    for (const auto& step : seq["steps"]) {
      const int first = step.contains("senders") ? step["senders"][0].get<int>() : step["sender"].get<int>();
      const int last = step.contains("senders") ? step["senders"][1].get<int>() : first;
      for (int k = first; k <= last; ++k) {
        const double at = step["at_s"];
        const double signed_s = step.value("signed_s", at);
        const std::string channel = step.value("channel", std::string("C"));
        std::vector<uint8_t> m = {1, 2};
        if (!step.value("unsigned", false))
          m = test::signedAs(step.value("other_key", false) ? other : key, senderOf(k), step["counter"],
                     base + static_cast<int64_t>(std::llround(signed_s * 1e6)), channel, m, step.value("replayed", false));
        if (step.contains("tamper")) m[step["tamper"].get<size_t>()] ^= 1;
        const Verdict v = verifier.checkAt(channel, m.data(), m.size(), base + static_cast<int64_t>(std::llround(at * 1e6)), at);
        const std::string got = v.accepted ? "accepted" : refusalName(v.why);
        EXPECT_EQ(got, step["expect"].get<std::string>()) << seq["name"] << ", step " << i << ", sender " << k;
        ++steps;
      }
      ++i;
    }
  }
  EXPECT_GT(steps, 500);
}

}  // namespace
}  // namespace igms::bus
