#pragma once
// One named product per AMD GPU family, for the roofline estimate (gpu/roofline.h) and the cache simulator
// (gpu/cache_sim.h): the public figures of src/gpu/families.json, embedded into the binary at build time. A
// family without an entry gets statistics but no estimate.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace aovar::gpu {

// Who shares one instance of a cache level: each CU (SM) has its own, each shader array, or the whole chip.
enum class CacheScope { cu, shader_array, chip };

// One level of a product's texture-path cache hierarchy. Sizes and bandwidth are per instance.
struct CacheLevelSpec {
  std::string name;  // "L0", "GL1", "L2", "Infinity Cache", "Texture cache"
  CacheScope scope = CacheScope::cu;
  int64_t size_bytes = 0;
  int line_bytes = 0;      // a power of two
  int ways = 0;            // set associativity; size_bytes / (line_bytes * ways) sets
  double bytes_per_clock = 0;  // peak, per instance, at the product's clock_mhz
  std::map<std::string, std::string> sources;  // figure ("size_kb", "ways", ...) -> key of cache_sources()
};

// The Mesa GL driver that compiles for a non-AMD product through its drm-shim (gpu/gl/vendor.h): a registered
// vendor's name and the value of its chip variable ("nouveau", "c8"). families.json's "compiler".
struct CompilerRef {
  std::string driver;
  std::string chip;
};

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
  std::string vendor = "amd";        // "nvidia" for a reference product
  double shader_clock_mhz = 0;       // the ALUs' clock where it differs from clock_mhz (Fermi), else 0
  int shader_engines = 1, shader_arrays_per_engine = 1;  // rasteriser groups: screen tiles go to arrays
  std::vector<CacheLevelSpec> caches;  // texture path, nearest the shader first; DRAM after the last
  std::optional<CompilerRef> compiler; // reference products a Mesa GL driver compiles for; none on AMD families
  double alu_lanes = 0;              // GL chips: fp32 lanes retiring one scalar instruction per ALU clock; 0: none
  std::string validation;            // GL chips: one line, the paper table the estimate was checked against
  double alu_clock_mhz() const { return shader_clock_mhz > 0 ? shader_clock_mhz : clock_mhz; }
  int shader_arrays() const { return shader_engines * shader_arrays_per_engine; }
};

// Every family of the embedded data file, in file order. Parsed once; throws std::runtime_error naming the
// entry when the embedded file is malformed (a build error in effect: tests/gpu/test_roofline.cpp checks it).
const std::vector<FamilySpec>& family_specs();

// The spec of `family` (or of a family it is an alias of); nullptr when the data file has none.
const FamilySpec* family_spec(const std::string& family);

// Products that are no RADV family (the GeForce GTX 580 of the SAO paper): the cache simulator can load them
// by name, ISA statistics never see them (family_specs() does not list them).
const std::vector<FamilySpec>& reference_products();

// The chips a Mesa GL driver compiles for: the reference products with a "compiler", in file order.
std::vector<const FamilySpec*> gl_chips();

// That chip by name or alias; nullptr when it is no GL chip.
const FamilySpec* gl_chip(const std::string& name);

// The product a frame-time estimate uses for `name`: an AMD family with an entry, or a GL chip with the
// figures its estimate needs (alu_lanes); nullptr for a chip that gets statistics only.
const FamilySpec* estimate_spec(const std::string& name);

// One line on how far to trust the estimate on `name` (select --target, ship --target): the paper table it was
// checked against with its Spearman and median ratio error (families.json's "validation", written from
// bench/gpu_seeds' output), "no validation" where no paper measured the chip, or that it has no estimate.
std::string validation_line(const std::string& name);

// A family (family_spec) or else a reference product, by name or alias; nullptr when neither has it.
const FamilySpec* product_spec(const std::string& name);

// The data file's citations: key -> text (author, title, year, section, URL).
const std::map<std::string, std::string>& cache_sources();

}  // namespace aovar::gpu
