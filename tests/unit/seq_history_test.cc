// SeqHistory (core/realtime/seq_history.h): a value is found by its key until the key N later takes
// its slot, never before it was written, and a reader on another thread never gets a torn copy.
#include "core/realtime/seq_history.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <thread>

namespace igms {
namespace {

struct Wide {  // wide enough that a torn copy would show: every word is the key it was written under
  int64_t word[16] = {};
};

Wide wide(int64_t key) {
  Wide w;
  for (int64_t& x : w.word) x = key;
  return w;
}

TEST(SeqHistory, AValueIsFoundByItsKeyUntilTheKeyNLaterTakesItsSlot) {
  SeqHistory<Wide, 8> history;
  Wide out;
  EXPECT_FALSE(history.read(0, &out)) << "never written";
  EXPECT_FALSE(history.read(3, &out));
  for (int64_t key = 0; key < 20; ++key) history.write(key, wide(key));
  for (int64_t key = 12; key < 20; ++key) {
    ASSERT_TRUE(history.read(key, &out)) << key;
    EXPECT_EQ(out.word[0], key);
    EXPECT_EQ(out.word[15], key);
  }
  for (int64_t key = 0; key < 12; ++key) EXPECT_FALSE(history.read(key, &out)) << key << ": overwritten";
  EXPECT_FALSE(history.read(20, &out)) << "not yet written";
  EXPECT_FALSE(history.read(28, &out));
}

TEST(SeqHistory, AReaderOnAnotherThreadNeverGetsATornCopy) {
  SeqHistory<Wide, 4> history;
  std::atomic<int64_t> written{-1};
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (int64_t key = 0; !stop; ++key) {
      history.write(key, wide(key));
      written.store(key, std::memory_order_release);
    }
  });
  // Reads the newest keys, those the writer is about to overwrite, until 50,000 were found (or 10 s).
  int64_t reads = 0, found = 0, torn = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (found < 50000 && std::chrono::steady_clock::now() < until) {
    const int64_t newest = written.load(std::memory_order_acquire);
    for (int64_t key = newest; key > newest - 4 && key >= 0; --key) {
      Wide out;
      ++reads;
      if (!history.read(key, &out)) continue;  // the writer has moved past it meanwhile
      ++found;
      for (const int64_t x : out.word) torn += x != key;
    }
  }
  stop = true;
  writer.join();
  std::printf("%lld reads, %lld found, %lld torn words\n", static_cast<long long>(reads),
              static_cast<long long>(found), static_cast<long long>(torn));
  EXPECT_EQ(torn, 0);
  EXPECT_GE(found, 50000) << "the reader raced the writer";
}

}  // namespace
}  // namespace igms
