// The random streams (core/rng.h): Pcg32::advance, which lets parallel work items read one stream
// at their own offsets (the light tiles' entries, LightTileStage), equals reading it in order.
#include <doctest/doctest.h>

#include <cstdint>

#include "core/rng.h"

using namespace rl;

TEST_SUITE("rng") {
  TEST_CASE("advance(k) leaves a stream where k outputs leave it, for every k, stream and seed tried") {
    for (uint64_t stream : {1ull, 7ull, 0x9e3779b97f4a7c15ull})
      for (uint64_t seed : {0ull, 42ull, 0xdeadbeefcafef00dull}) {
        CAPTURE(stream);
        CAPTURE(seed);
        Pcg32 in_order(seed, stream);
        uint64_t read = 0;
        for (uint64_t k : {0ull, 1ull, 2ull, 3ull, 17ull, 1024ull, 4097ull, 65536ull}) {
          CAPTURE(k);
          while (read < k) in_order.next_u32(), ++read;
          Pcg32 skipped(seed, stream);
          skipped.advance(k);
          CHECK(skipped.state == in_order.state);
          CHECK(skipped.next_u32() == Pcg32(in_order).next_u32());
        }
        // Composition: advance(a) then advance(b) is advance(a + b), here past 2^32 outputs.
        Pcg32 a(seed, stream), b(seed, stream);
        a.advance(uint64_t(1) << 33), a.advance(12345);
        b.advance((uint64_t(1) << 33) + 12345);
        CHECK(a.state == b.state);
      }
  }

  TEST_CASE("advance has power: an off-by-one skip lands elsewhere") {
    Pcg32 in_order(5, 3);
    for (int i = 0; i < 100; ++i) in_order.next_u32();
    Pcg32 skipped(5, 3);
    skipped.advance(99);
    CHECK(skipped.state != in_order.state);
    CHECK(skipped.next_u32() != in_order.next_u32());
  }
}
