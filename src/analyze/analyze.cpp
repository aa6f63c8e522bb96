// SPIR-V static cost walker: see analyze.h. The module is read word by word (no SPIRV-Tools opt IR: its
// headers are not installed); SPIR-V 1.x opcode numbers below are from the unified spec.
#include "analyze/analyze.h"
#include "util/fs.h"
#include "util/schema.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <nlohmann/json.hpp>

namespace aovar::analyze {
namespace {

enum Op : std::uint32_t {
  OpName = 5, OpExtInstImport = 11, OpExtInst = 12, OpEntryPoint = 15, OpTypeInt = 21, OpConstant = 43,
  OpFunction = 54, OpFunctionParameter = 55, OpFunctionEnd = 56, OpFunctionCall = 57, OpVariable = 59,
  OpLoad = 61, OpStore = 62, OpAccessChain = 65, OpInBoundsAccessChain = 66, OpDecorate = 71,
  OpCopyObject = 83, OpSampledImage = 86, OpImage = 100, OpIAdd = 128, OpISub = 130, OpINotEqual = 171,
  OpUGreaterThan = 172, OpSGreaterThan = 173, OpUGreaterThanEqual = 174, OpSGreaterThanEqual = 175,
  OpULessThan = 176, OpSLessThan = 177, OpULessThanEqual = 178, OpSLessThanEqual = 179, OpPhi = 245,
  OpLoopMerge = 246, OpSelectionMerge = 247, OpLabel = 248, OpBranch = 249, OpBranchConditional = 250,
  OpSwitch = 251, OpKill = 252, OpReturn = 253, OpReturnValue = 254, OpUnreachable = 255,
  OpTerminateInvocation = 4416,
};
constexpr std::uint32_t kDecorationBinding = 33;

bool is_texture_read(std::uint32_t op) {
  return (op >= 87 && op <= 98) || (op >= 305 && op <= 315) || op == 320;
}
bool is_alu(std::uint32_t op) {
  return (op >= 109 && op <= 116) || op == 124 || (op >= 126 && op <= 152) || (op >= 194 && op <= 205) ||
         (op >= 207 && op <= 215);
}
bool is_div(std::uint32_t op) { return op >= 134 && op <= 141; }
bool is_cmp_select(std::uint32_t op) { return op >= 154 && op <= 191; }
bool is_transcendental(std::uint32_t glsl) {  // GLSL.std.450: Sin..Atan2 (13..25), Pow..InverseSqrt (26..32)
  return glsl >= 13 && glsl <= 32;
}
constexpr std::uint32_t kGlslFma = 50, kGlslLength = 66, kGlslDistance = 67, kGlslNormalize = 69;

struct Inst {
  std::uint32_t op;
  std::vector<std::uint32_t> w;  // operand words (without the opcode word)
  // Operand `i`, or 0 (never a valid id or a meaningful count) past the end: a malformed module's short
  // instruction then reads as "not what the analysis looks for" instead of out of bounds (found by fuzzing).
  std::uint32_t at(std::size_t i) const { return i < w.size() ? w[i] : 0; }
};

struct Block {
  std::uint32_t label = 0;
  std::vector<int> insts;  // indices into Module::insts
  std::vector<std::uint32_t> succ;
  std::uint32_t merge = 0, cont = 0, loop_control = 0;
  bool loop = false;
  int terminator = -1;
};

struct Function {
  std::uint32_t id = 0;
  std::vector<Block> blocks;
  std::unordered_map<std::uint32_t, int> block_of_label;
};

std::string literal_string(const std::vector<std::uint32_t>& w, std::size_t from) {
  std::string s;
  for (std::size_t i = from; i < w.size(); ++i) {
    char c[4];
    std::memcpy(c, &w[i], 4);
    for (char ch : c) {
      if (!ch) return s;
      s += ch;
    }
  }
  return s;
}

struct Module {
  std::vector<Inst> insts;
  std::unordered_map<std::uint32_t, int> def;  // result id -> instruction index
  std::unordered_map<std::uint32_t, std::string> names;
  std::unordered_map<std::uint32_t, int> binding;
  std::unordered_map<std::uint32_t, std::pair<int, bool>> int_types;  // width, signed
  std::set<std::uint32_t> glsl_sets;
  std::vector<Function> functions;
  std::unordered_map<std::uint32_t, int> function_of_id;
  std::unordered_map<int, int> block_of_inst;  // instruction index -> block index in its function
  std::uint32_t entry = 0;

  const Inst* def_of(std::uint32_t id) const {
    auto it = def.find(id);
    return it == def.end() ? nullptr : &insts[it->second];
  }
  std::optional<long long> int_constant(std::uint32_t id) const {
    const Inst* i = def_of(id);
    if (!i || i->op != OpConstant || i->w.size() < 3) return std::nullopt;
    auto t = int_types.find(i->at(0));
    if (t == int_types.end() || t->second.first != 32) return std::nullopt;
    return t->second.second ? static_cast<long long>(static_cast<std::int32_t>(i->at(2)))
                            : static_cast<long long>(i->at(2));
  }
  int resolve_binding(std::uint32_t id) const {
    for (int guard = 0; guard < 32; ++guard) {
      auto b = binding.find(id);
      if (b != binding.end()) return b->second;
      const Inst* i = def_of(id);
      if (!i || i->w.size() < 3) return -1;
      switch (i->op) {
        case OpLoad: case OpSampledImage: case OpImage: case OpAccessChain: case OpInBoundsAccessChain:
        case OpCopyObject:
          id = i->at(2);
          break;
        default:
          return -1;
      }
    }
    return -1;
  }
};

bool has_result(std::uint32_t op) {  // the instructions whose result id this walker needs (word 1)
  switch (op) {
    case OpConstant: case OpFunctionParameter: case OpFunctionCall: case OpVariable: case OpLoad:
    case OpAccessChain: case OpInBoundsAccessChain: case OpCopyObject: case OpSampledImage: case OpImage:
    case OpPhi: case OpExtInst:
      return true;
    default:
      return (op >= 109 && op <= 215);
  }
}

Module parse(const std::vector<std::uint32_t>& words) {
  if (words.size() < 5 || words[0] != 0x07230203u)
    throw std::runtime_error("not a SPIR-V module (bad magic number or too short)");
  Module m;
  Function* fn = nullptr;
  Block* blk = nullptr;
  for (std::size_t pos = 5; pos < words.size();) {
    std::uint32_t count = words[pos] >> 16, op = words[pos] & 0xffffu;
    if (count == 0 || pos + count > words.size())
      throw std::runtime_error(fmt::format("malformed SPIR-V: instruction at word {} overruns the module", pos));
    Inst in{op, std::vector<std::uint32_t>(words.begin() + pos + 1, words.begin() + pos + count)};
    pos += count;
    int idx = static_cast<int>(m.insts.size());
    const auto& w = in.w;
    switch (op) {
      case OpName: if (w.size() >= 1) m.names[w[0]] = literal_string(w, 1); break;
      case OpExtInstImport: if (w.size() >= 1 && literal_string(w, 1) == "GLSL.std.450") m.glsl_sets.insert(w[0]); break;
      case OpEntryPoint: if (w.size() >= 2 && !m.entry) m.entry = w[1]; break;
      case OpTypeInt: if (w.size() >= 3) m.int_types[w[0]] = {static_cast<int>(w[1]), w[2] != 0}; break;
      case OpDecorate: if (w.size() >= 3 && w[1] == kDecorationBinding) m.binding[w[0]] = static_cast<int>(w[2]); break;
      case OpFunction:
        m.functions.emplace_back();
        fn = &m.functions.back();
        fn->id = w.size() >= 2 ? w[1] : 0;
        m.function_of_id[fn->id] = static_cast<int>(m.functions.size()) - 1;
        blk = nullptr;
        break;
      case OpFunctionEnd: fn = nullptr; blk = nullptr; break;
      case OpLabel:
        if (fn) {
          fn->blocks.emplace_back();
          blk = &fn->blocks.back();
          blk->label = w.at(0);
          fn->block_of_label[blk->label] = static_cast<int>(fn->blocks.size()) - 1;
        }
        break;
      default: break;
    }
    if (has_result(op) && w.size() >= 2) m.def[w[1]] = idx;
    if (blk && op != OpLabel) {
      m.block_of_inst[idx] = static_cast<int>(fn->blocks.size()) - 1;
      blk->insts.push_back(idx);
      switch (op) {
        case OpLoopMerge: blk->loop = true; blk->merge = w.at(0); blk->cont = w.at(1); blk->loop_control = w.at(2); break;
        case OpSelectionMerge: blk->merge = blk->loop ? blk->merge : w.at(0); break;
        case OpBranch: blk->succ = {w.at(0)}; blk->terminator = idx; break;
        case OpBranchConditional: blk->succ = {w.at(1), w.at(2)}; blk->terminator = idx; break;
        case OpSwitch:
          blk->succ = {w.at(1)};
          for (std::size_t i = 3; i < w.size(); i += 2) blk->succ.push_back(w[i]);
          blk->terminator = idx;
          break;
        case OpKill: case OpReturn: case OpReturnValue: case OpUnreachable: case OpTerminateInvocation:
          blk->terminator = idx;
          break;
        default: break;
      }
    }
    m.insts.push_back(std::move(in));
  }
  return m;
}

struct LoopFound {
  int header;
  std::set<int> body;  // block indices (header included)
  LoopInfo info;
};

// Trip count of a loop in glslang's unoptimised `for` pattern, or nullopt.
std::optional<long long> trip_count(const Module& m, const Function& f, const LoopFound& loop) {
  const Block& h = f.blocks[loop.header];
  auto exit_branch = [&](const Block& b) -> const Inst* {
    if (b.terminator < 0) return nullptr;
    const Inst& t = m.insts[b.terminator];
    if (t.op == OpBranchConditional && (t.at(1) == h.merge || t.at(2) == h.merge)) return &t;
    return nullptr;
  };
  const Inst* br = exit_branch(h);
  if (!br && h.succ.size() == 1) {
    auto it = f.block_of_label.find(h.succ[0]);
    if (it != f.block_of_label.end()) br = exit_branch(f.blocks[it->second]);
  }
  if (!br) return std::nullopt;
  bool continue_on_true = br->at(1) != h.merge;
  const Inst* cmp = m.def_of(br->at(0));
  if (!cmp || cmp->w.size() < 4) return std::nullopt;
  enum Rel { lt, le, gt, ge, ne, eq };
  Rel rel;
  switch (cmp->op) {
    case OpSLessThan: case OpULessThan: rel = lt; break;
    case OpSLessThanEqual: case OpULessThanEqual: rel = le; break;
    case OpSGreaterThan: case OpUGreaterThan: rel = gt; break;
    case OpSGreaterThanEqual: case OpUGreaterThanEqual: rel = ge; break;
    case OpINotEqual: rel = ne; break;
    default: return std::nullopt;
  }
  std::uint32_t a = cmp->at(2), b = cmp->at(3);
  auto bound = m.int_constant(b);
  if (!bound) {  // constant on the left: B < i  <=>  i > B
    bound = m.int_constant(a);
    if (!bound) return std::nullopt;
    std::swap(a, b);
    rel = rel == lt ? gt : rel == le ? ge : rel == gt ? lt : rel == ge ? le : rel;
  }
  if (!continue_on_true) rel = rel == lt ? ge : rel == le ? gt : rel == gt ? le : rel == ge ? lt : eq;
  if (rel == eq) return std::nullopt;

  // The induction value: a load of a Function variable, or an OpPhi in the header.
  std::optional<long long> init, step;
  auto in_loop = [&](int inst_index) {
    auto it = m.block_of_inst.find(inst_index);
    return it != m.block_of_inst.end() && loop.body.count(it->second) > 0;
  };
  auto step_of = [&](std::uint32_t value, auto&& is_induction) -> std::optional<long long> {
    const Inst* add = m.def_of(value);
    if (!add || (add->op != OpIAdd && add->op != OpISub) || add->w.size() < 4) return std::nullopt;
    std::uint32_t x = add->at(2), c = add->at(3);
    auto k = m.int_constant(c);
    if (!k && add->op == OpIAdd) { std::swap(x, c); k = m.int_constant(c); }
    if (!k || !is_induction(x)) return std::nullopt;
    return add->op == OpIAdd ? *k : -*k;
  };
  const Inst* ind = m.def_of(a);
  if (!ind) return std::nullopt;
  if (ind->op == OpLoad) {
    std::uint32_t var = ind->at(2);
    const Inst* v = m.def_of(var);
    if (!v || v->op != OpVariable) return std::nullopt;
    auto loads_var = [&](std::uint32_t x) {
      const Inst* l = m.def_of(x);
      return l && l->op == OpLoad && l->at(2) == var;
    };
    int outside = 0;
    for (std::size_t fb = 0; fb < f.blocks.size(); ++fb)
      for (int ii : f.blocks[fb].insts) {
        const Inst& s = m.insts[ii];
        if (s.op != OpStore || s.at(0) != var) continue;
        if (in_loop(ii)) {
          auto k = step_of(s.at(1), loads_var);
          if (!k || (step && *step != *k)) return std::nullopt;
          step = k;
        } else {
          ++outside;
          init = m.int_constant(s.at(1));
        }
      }
    if (outside != 1) return std::nullopt;
  } else if (ind->op == OpPhi) {
    std::uint32_t phi = a;
    for (std::size_t i = 2; i + 1 < ind->w.size(); i += 2) {
      auto pb = f.block_of_label.find(ind->at(i + 1));
      if (pb == f.block_of_label.end()) return std::nullopt;
      if (loop.body.count(pb->second)) {
        auto k = step_of(ind->at(i), [&](std::uint32_t x) { return x == phi; });
        if (!k || (step && *step != *k)) return std::nullopt;
        step = k;
      } else {
        if (init) return std::nullopt;
        init = m.int_constant(ind->at(i));
      }
    }
  } else {
    return std::nullopt;
  }
  if (!init || !step || *step == 0) return std::nullopt;
  long long A = *init, B = *bound, s = *step;
  auto ceil_div = [](long long x, long long d) { return x <= 0 ? 0 : (x + d - 1) / d; };
  switch (rel) {
    case lt: if (s > 0) return ceil_div(B - A, s); break;
    case le: if (s > 0) return ceil_div(B - A + 1, s); break;
    case gt: if (s < 0) return ceil_div(A - B, -s); break;
    case ge: if (s < 0) return ceil_div(A - B + 1, -s); break;
    case ne: if ((B - A) % s == 0 && (B - A) / s >= 0) return (B - A) / s; break;
    default: break;
  }
  return std::nullopt;
}

bool starts_with(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

struct Analyzer {
  const Module& m;
  std::unordered_map<std::uint32_t, ProgramCost> memo;
  std::set<std::uint32_t> active;
  std::vector<LoopInfo> all_loops;
  std::set<std::uint32_t> loops_listed;

  std::string fname(std::uint32_t id) const {
    auto it = m.names.find(id);
    return it == m.names.end() ? fmt::format("%{}", id) : it->second;
  }

  ProgramCost function_cost(std::uint32_t fid) {
    if (auto it = memo.find(fid); it != memo.end()) return it->second;
    auto fi = m.function_of_id.find(fid);
    if (fi == m.function_of_id.end() || !active.insert(fid).second) return {};  // no recursion in GLSL
    const Function& f = m.functions[fi->second];
    // Loops: blocks reachable from the header without entering its merge block.
    std::vector<LoopFound> loops;
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      const Block& h = f.blocks[b];
      if (!h.loop) continue;
      LoopFound lf{static_cast<int>(b), {}, {}};
      std::vector<int> stack{static_cast<int>(b)};
      while (!stack.empty()) {
        int cur = stack.back();
        stack.pop_back();
        if (!lf.body.insert(cur).second) continue;
        for (auto s : f.blocks[cur].succ) {
          if (s == h.merge) continue;
          auto it = f.block_of_label.find(s);
          if (it != f.block_of_label.end() && !lf.body.count(it->second)) stack.push_back(it->second);
        }
      }
      loops.push_back(std::move(lf));
    }
    for (auto& lf : loops) {
      auto trips = trip_count(m, f, lf);
      lf.info.function = fname(fid);
      lf.info.constant = trips.has_value();
      lf.info.trips = trips.value_or(1);
      lf.info.unroll_hint = (f.blocks[lf.header].loop_control & 1u) != 0;
      lf.info.dont_unroll_hint = (f.blocks[lf.header].loop_control & 2u) != 0;
      for (const auto& other : loops)
        if (&other != &lf && other.body.count(lf.header)) ++lf.info.depth;
    }
    std::vector<double> mult(f.blocks.size(), 1.0);
    for (const auto& lf : loops)
      for (int b : lf.body) mult[b] *= static_cast<double>(lf.info.trips);

    ProgramCost c;
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      double k = mult[b];
      for (int ii : f.blocks[b].insts) {
        const Inst& in = m.insts[ii];
        std::uint32_t op = in.op;
        if (is_texture_read(op) && in.w.size() >= 3) c.fetches[m.resolve_binding(in.at(2))] += k;
        else if (is_alu(op)) {
          c.alu += k;
          if (is_div(op)) c.div += k;
        } else if (is_cmp_select(op)) c.cmp_select += k;
        else if (op == OpBranchConditional || op == OpSwitch) c.branches += k;
        else if (op == OpExtInst && in.w.size() >= 4 && m.glsl_sets.count(in.at(2))) {
          std::uint32_t g = in.at(3);
          c.alu += k;
          if (g == kGlslFma) c.fma += k;
          if (is_transcendental(g)) c.transcendental += k;
          if (g == kGlslLength || g == kGlslDistance || g == kGlslNormalize) c.normalize_length += k;
        } else if (op == OpFunctionCall && in.w.size() >= 3) {
          std::uint32_t callee = in.at(2);
          std::string name = fname(callee);
          c.calls += k;
          if (starts_with(name, "ao_view_position_from_depth(")) c.unprojections += k;
          if (starts_with(name, "ao_uv_from_view_position(")) c.projections += k;
          if (starts_with(name, "ao_position(")) c.position_calls += k;
          ProgramCost sub = function_cost(callee);
          sub.loops.clear();
          c += sub.scaled(k);
        }
      }
    }
    if (loops_listed.insert(fid).second)
      for (const auto& lf : loops) all_loops.push_back(lf.info);
    active.erase(fid);
    memo[fid] = c;
    return c;
  }
};

}  // namespace

double ProgramCost::total_fetches() const {
  double t = 0;
  for (const auto& [b, n] : fetches) t += n;
  return t;
}
bool ProgramCost::has_dynamic_loop() const {
  return std::any_of(loops.begin(), loops.end(), [](const LoopInfo& l) { return !l.constant; });
}
ProgramCost& ProgramCost::operator+=(const ProgramCost& o) {
  for (const auto& [b, n] : o.fetches) fetches[b] += n;
  alu += o.alu; fma += o.fma; div += o.div; transcendental += o.transcendental;
  normalize_length += o.normalize_length; cmp_select += o.cmp_select; branches += o.branches;
  calls += o.calls; unprojections += o.unprojections; projections += o.projections; position_calls += o.position_calls;
  loops.insert(loops.end(), o.loops.begin(), o.loops.end());
  if (error.empty()) error = o.error;
  return *this;
}
ProgramCost ProgramCost::scaled(double k) const {
  ProgramCost c = *this;
  for (auto& [b, n] : c.fetches) n *= k;
  for (double* v : {&c.alu, &c.fma, &c.div, &c.transcendental, &c.normalize_length, &c.cmp_select, &c.branches,
                    &c.calls, &c.unprojections, &c.projections, &c.position_calls})
    *v *= k;
  return c;
}

ProgramCost analyze_spirv(const std::vector<std::uint32_t>& words) {
  Module m = parse(words);
  if (!m.entry) throw std::runtime_error("SPIR-V module has no entry point");
  Analyzer a{m, {}, {}, {}, {}};
  ProgramCost c = a.function_cost(m.entry);
  c.loops = a.all_loops;  // loops of the entry point and of every function it calls, each listed once
  return c;
}

double bytes_per_pixel(const std::map<int, double>& fetches, const std::map<int, int>& bytes_per_texel) {
  double bytes = 0;
  for (const auto& [b, n] : fetches)
    if (auto it = bytes_per_texel.find(b); it != bytes_per_texel.end()) bytes += n * it->second;
  return bytes;
}

std::map<int, int> binding_bytes(const std::string& depth_format, const std::string& normals) {
  std::map<int, int> m;
  m[kDepth] = depth_format == "r16f" ? 2 : 4;
  m[kNormal] = normals == "rgb8" ? 4 : (normals == "rg8" || normals == "oct16") ? 2 : 0;
  m[kPosition] = 16;
  m[kInput] = 4;
  m[kHistory] = 4;
  m[kPrefilter] = 4;
  return m;
}

namespace {

std::vector<std::uint32_t> read_words(const std::filesystem::path& p) {
  const std::optional<std::string> read = util::read_file(p);
  if (!read) throw std::runtime_error(p.string() + ": error: cannot open (run `aovar generate --emit index,spirv`)");
  const std::string& bytes = *read;
  if (bytes.size() % 4) throw std::runtime_error(p.string() + ": error: size is not a multiple of 4 bytes");
  std::vector<std::uint32_t> w(bytes.size() / 4);
  if (!w.empty()) std::memcpy(w.data(), bytes.data(), bytes.size());
  return w;
}

nlohmann::ordered_json cost_json(const ProgramCost& c, const std::map<int, int>* bytes) {
  static const std::map<int, const char*> names = {{-1, "unknown"}, {kDepth, "depth"}, {kNormal, "normal"},
                                                   {kPosition, "position"}, {kInput, "input"},
                                                   {kHistory, "history"}, {kPrefilter, "prefilter"}};
  nlohmann::ordered_json f = nlohmann::ordered_json::object();
  for (const auto& [b, n] : c.fetches) {
    auto it = names.find(b);
    f[it != names.end() ? std::string(it->second) : fmt::format("binding{}", b)] = n;
  }
  nlohmann::ordered_json j;
  j["fetches"] = f;
  j["alu"] = c.alu;
  j["fma"] = c.fma;
  j["div"] = c.div;
  j["transcendental"] = c.transcendental;
  j["normalize_length"] = c.normalize_length;
  j["cmp_select"] = c.cmp_select;
  j["branches"] = c.branches;
  j["unprojections"] = c.unprojections;
  j["projections"] = c.projections;
  j["position_calls"] = c.position_calls;
  if (bytes) j["bytes_per_pixel"] = bytes_per_pixel(c.fetches, *bytes);
  nlohmann::ordered_json loops = nlohmann::ordered_json::array();
  for (const auto& l : c.loops) {
    nlohmann::ordered_json e;
    e["function"] = l.function;
    e["depth"] = l.depth;
    e["trips"] = l.constant ? nlohmann::ordered_json(l.trips) : nlohmann::ordered_json("dynamic");
    e["unrolled"] = false;
    if (l.unroll_hint) e["hint"] = "unroll";
    if (l.dont_unroll_hint) e["hint"] = "dont_unroll";
    loops.push_back(e);
  }
  j["loops"] = loops;
  j["upper_bound"] = true;
  if (!c.error.empty()) j["error"] = c.error;
  return j;
}

std::string loops_text(const ProgramCost& c) {
  int constant = 0, dynamic = 0;
  for (const auto& l : c.loops) (l.constant ? constant : dynamic)++;
  if (!constant && !dynamic) return "none";
  std::string s;
  for (const auto& l : c.loops) s += (s.empty() ? "" : "x") + (l.constant ? std::to_string(l.trips) : std::string("dyn"));
  return s + " (not unrolled)";
}

}  // namespace

Analysis analyze_folder(const std::filesystem::path& dir) {
  auto index_path = dir / "variants.json";
  const std::optional<std::string> in = util::read_file(index_path);
  if (!in)
    throw std::runtime_error(index_path.string() +
                             ": error: cannot open (run `aovar generate --out DIR --emit index,spirv` first)");
  nlohmann::ordered_json idx;
  try {
    idx = nlohmann::ordered_json::parse(*in);
  } catch (const std::exception& e) {
    throw std::runtime_error(index_path.string() + ": error: " + e.what());
  }
  util::check_schema(idx, index_path);
  if (!idx.contains("programs") || !idx["programs"].contains("vulkan"))
    throw std::runtime_error(index_path.string() + ": error: no vulkan programs (generate with --targets vulkan)");
  Analysis a;
  std::map<std::string, int> row_of;
  for (const auto& p : idx["programs"]["vulkan"]) {
    std::string key = p.value("key", "");
    if (key.size() < 5 || key.substr(key.size() - 5) != ".frag") continue;
    ProgramRow r;
    r.key = key;
    r.same_as = p.value("same_as", "");
    std::string file = r.same_as.empty() ? key : r.same_as;
    try {
      r.cost = analyze_spirv(read_words(dir / "vulkan" / (file + ".spv")));
    } catch (const std::exception& e) {
      r.cost.error = e.what();
    }
    row_of[key] = static_cast<int>(a.programs.size());
    a.programs.push_back(std::move(r));
  }
  std::vector<std::string> axis_names;
  if (idx.contains("axes"))
    for (const auto& [name, values] : idx["axes"].items()) axis_names.push_back(name);
  for (const auto& v : idx.value("variants", nlohmann::ordered_json::array())) {
    VariantRow row;
    row.key = v.value("key", "");
    std::map<std::string, std::string> axes;
    if (v.contains("axes"))
      for (std::size_t i = 0; i < v["axes"].size() && i < axis_names.size(); ++i)
        axes[axis_names[i]] = v["axes"][i].is_string() ? v["axes"][i].get<std::string>() : v["axes"][i].dump();
    auto bytes = binding_bytes(axes["depth_format"], axes["normals"]);
    if (v.contains("passes"))
      for (const auto& [pass, prog] : v["passes"].items()) {
        std::string key = prog.get<std::string>();
        row.passes[pass] = key;
        auto it = row_of.find(key);
        if (it == row_of.end()) continue;
        const ProgramCost& c = a.programs[it->second].cost;
        if (pass == "ao") row.ao = c;
        row.total += c;
      }
    row.ao_bytes = bytes_per_pixel(row.ao.fetches, bytes);
    row.total_bytes = bytes_per_pixel(row.total.fetches, bytes);
    a.variants.push_back(std::move(row));
  }
  return a;
}

std::string analysis_json(const Analysis& a) {
  nlohmann::ordered_json j;
  j["schema_version"] = util::kSchemaVersion;
  j["note"] = "static counts per pixel of each program's pass, loops multiplied through (upper bounds: "
              "branches that skip work are counted); variant totals sum each pass's fragment program once";
  nlohmann::ordered_json progs = nlohmann::ordered_json::array();
  for (const auto& p : a.programs) {
    nlohmann::ordered_json e;
    e["program"] = p.key;
    if (!p.same_as.empty()) e["same_as"] = p.same_as;
    e["static"] = cost_json(p.cost, nullptr);
    progs.push_back(e);
  }
  j["programs"] = progs;
  nlohmann::ordered_json vars = nlohmann::ordered_json::array();
  for (const auto& v : a.variants) {
    nlohmann::ordered_json e;
    e["variant"] = v.key;
    e["passes"] = v.passes;
    auto ao = cost_json(v.ao, nullptr);
    ao["bytes_per_pixel"] = v.ao_bytes;
    auto total = cost_json(v.total, nullptr);
    total["bytes_per_pixel"] = v.total_bytes;
    total.erase("loops");
    e["ao"] = ao;
    e["total"] = total;
    vars.push_back(e);
  }
  j["variants"] = vars;
  return j.dump(1) + "\n";
}

std::string program_table(const Analysis& a) {
  std::ostringstream out;
  out << fmt::format("{:<44} {:>6} {:>6} {:>6} {:>6} {:>6} {:>7} {:>5} {:>5} {:>6} {:>7} {:>6} {:>6} {:>5}  {}\n", "program",
                     "depth", "normal", "posit", "input", "prefil", "alu", "fma", "div", "transc", "cmp/sel",
                     "branch", "unproj", "proj", "loops");
  for (const auto& p : a.programs) {
    if (!p.cost.error.empty()) {
      out << fmt::format("{:<44} error: {}\n", p.key, p.cost.error);
      continue;
    }
    const auto& c = p.cost;
    out << fmt::format("{:<44} {:>6g} {:>6g} {:>6g} {:>6g} {:>6g} {:>7g} {:>5g} {:>5g} {:>6g} {:>7g} {:>6g} {:>6g} {:>5g}  {}\n",
                       p.key, c.fetch(kDepth), c.fetch(kNormal), c.fetch(kPosition), c.fetch(kInput) + c.fetch(kHistory),
                       c.fetch(kPrefilter), c.alu, c.fma, c.div, c.transcendental, c.cmp_select, c.branches,
                       c.unprojections, c.projections, loops_text(c));
  }
  return out.str();
}

}  // namespace aovar::analyze
