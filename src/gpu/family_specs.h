#pragma once
// One named product per AMD GPU family, for the roofline estimate (gpu/roofline.h): the public figures of
// src/gpu/families.json, embedded into the binary at build time. A family without an entry gets
// statistics but no estimate.
#include <string>
#include <vector>

namespace aovar::gpu {

struct FamilySpec {
  std::string family;                // RADV's name ("navi21")
  std::vector<std::string> aliases;  // other RADV names for the same chip ("gfx1100" for navi31)
  std::string product;               // "Radeon RX 6800 XT"
  int cus = 0, simds_per_cu = 0;     // compute units; SIMDs per CU (GCN 4 x SIMD16, RDNA 2 x SIMD32)
  int wave_size = 64;                // what RADV compiles fragment shaders with on this family
  double clock_mhz = 0;              // boost clock
  double tmus = 0;                   // texture units (filtered fetches per clock)
  double bandwidth_gbs = 0;          // memory bandwidth, GB/s
  std::string source;                // public page the figures come from
};

// Every family of the embedded data file, in file order. Parsed once; throws std::runtime_error naming the
// entry when the embedded file is malformed (a build error in effect: tests/test_roofline.cpp checks it).
const std::vector<FamilySpec>& family_specs();

// The spec of `family` (or of a family it is an alias of); nullptr when the data file has none.
const FamilySpec* family_spec(const std::string& family);

}  // namespace aovar::gpu
