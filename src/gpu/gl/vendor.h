#pragma once
// A GPU vendor whose Mesa GL driver compiles without the hardware: Mesa's drm-shim (a preload library that
// fakes the render node, as Mesa's shader-db uses it) makes the driver believe the chip an environment
// variable names is present, and the driver reports each compiled shader's statistics through KHR_debug.
// One file per vendor (gpu/gl/vendors/<name>.cpp) says how to start its driver and how to read its line; the list
// in gpu/gl/vendors.cpp registers them. A chip of a known vendor is a data entry (families.json's "compiler").
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gpu/stats.h"

namespace aovar::gpu {

struct GlVendor {
  std::string name;           // "nouveau": families.json's compiler.driver
  std::string title;          // "NVIDIA (nouveau)"
  std::string arch;           // the Debian architecture its driver is built for: "amd64", or "arm64" (qemu-user)
  std::string shim;           // the noop drm-shim library's file name
  std::string chip_variable;  // the variable that names the chip: "NOUVEAU_CHIPSET"
  std::vector<std::pair<std::string, std::string>> env;  // what else makes the driver print its statistics
  // The fragment program's statistics among one program's compiler messages (one line each), or nothing.
  std::optional<ShaderStats> (*fragment_stats)(const std::vector<std::string>& messages) = nullptr;
  // The estimate's ALU term (gpu/gl/estimate.h): the lane-cycles one pixel's program takes, the issue slots the
  // vendor's statistics count per thread, to be divided by the chip's alu_lanes (families.json); NaN when the
  // statistics lack the count.
  double (*alu_lane_cycles)(const ShaderStats& stats) = nullptr;
};

// Every registered vendor (gpu/gl/vendors.cpp), in a fixed order.
const std::vector<const GlVendor*>& gl_vendors();

// The vendor of that name; nullptr when none is registered.
const GlVendor* gl_vendor(const std::string& name);

// "565 inst, 12 nops, 0:0 spills:fills" -> {"inst": 565, "nops": 12, "spills": 0, "fills": 0}: the counts a
// shader-db line lists as "<number> <name>" (or "a:b x:y") between commas; other fields are skipped.
std::map<std::string, double> counted_fields(const std::string& list);

// The last message that holds `tag` (a shader's statistics line: the driver may report a program more than
// once, the last is what was kept), or nothing.
const std::string* last_line_with(const std::vector<std::string>& messages, const std::string& tag);

// The value of `name` in `values`, NaN when it is missing; the sum of several, NaN when all are missing.
double field(const std::map<std::string, double>& values, const std::string& name);
double field_sum(const std::map<std::string, double>& values, const std::vector<std::string>& names);

// One shader-db line's statistics: its fields `values`, the line itself and its `inst`, the instruction count
// every vendor's line holds. The vendor reads its other fields.
ShaderStats line_stats(std::map<std::string, double> values, const std::string& line);

// The last message holding `tag` (last_line_with) read as "<tag> <counted fields>", the form most vendors print;
// nothing when no message holds it.
std::optional<ShaderStats> tagged_line_stats(const std::vector<std::string>& messages, const std::string& tag);

// The ALU term (GlVendor::alu_lane_cycles) of a vendor whose every counted instruction takes one issue slot per
// thread: the instruction count. Each vendor's file says why that holds for its hardware.
double instructions_issued(const ShaderStats& stats);

}  // namespace aovar::gpu
