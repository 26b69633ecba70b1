// Counts heap allocations in this process (operator new and malloc are
// replaced in malloc_counter.cc), for the no-allocation tests.
#pragma once

#include <cstddef>

namespace igms::test {

size_t allocationCount();

// Allocations made while running f.
template <typename F>
size_t allocationsDuring(F&& f) {
  const size_t before = allocationCount();
  f();
  return allocationCount() - before;
}

}  // namespace igms::test
