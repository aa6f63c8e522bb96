#include "trace/traffic_cache.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "util/fs.h"
#include "util/hash.h"

namespace aovar::trace {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// This build, by content: a rebuilt simulator or trace build never reads another build's results.
const std::string& build_hash() {
  static const std::string hash = [] {
    const auto exe = util::read_file("/proc/self/exe");
    return exe ? util::hash_hex(*exe) : std::string("unknown");
  }();
  return hash;
}

json to_json(const gpu::CacheSimResult& r) {
  json levels = json::array();
  for (const auto& l : r.levels)
    levels.push_back({l.name, l.line_bytes, l.accesses, l.hits, l.unique_lines, l.bytes_requested});
  return {{"product", r.product}, {"pixels", r.pixels}, {"reads", r.reads}, {"dram_bytes", r.dram_bytes},
          {"levels", levels}};
}

gpu::CacheSimResult from_json(const json& j) {
  gpu::CacheSimResult r;
  r.product = j.at("product").get<std::string>();
  r.pixels = j.at("pixels").get<int64_t>();
  r.reads = j.at("reads").get<int64_t>();
  r.dram_bytes = j.at("dram_bytes").get<int64_t>();
  for (const auto& l : j.at("levels"))
    r.levels.push_back({l.at(0).get<std::string>(), l.at(1).get<int>(), l.at(2).get<int64_t>(), l.at(3).get<int64_t>(),
                        l.at(4).get<int64_t>(), l.at(5).get<int64_t>()});
  return r;
}

}  // namespace

TrafficCache::TrafficCache(fs::path dir, std::string view_context)
    : cache_(std::move(dir), "traffic"), context_(std::move(view_context)) {}

std::string TrafficCache::key(const std::string& draw_key, const std::string& family) const {
  util::Hasher h;  // the parts length-prefixed, so no two keys run together
  h.add(build_hash()).add(context_).add(draw_key).add(family);
  return "traffic " + h.hex() + " " + family + " " + draw_key;
}

std::optional<CachedTraffic> TrafficCache::find(const std::string& draw_key, const std::string& family) const {
  const std::string k = key(draw_key, family);
  const auto text = cache_.read(k);
  if (!text) return std::nullopt;
  const json j = json::parse(*text, nullptr, false);
  try {  // a damaged entry is a miss: the draw is simulated again and the entry rewritten
    CachedTraffic t;
    t.absent = j.at("absent").get<bool>();
    if (!t.absent) t.result = from_json(j.at("result"));
    if (!t.absent && !(t.result.pixels > 0 && t.result.reads >= 0 && t.result.dram_bytes >= 0))
      throw std::runtime_error("a result no simulation gives (pixels, reads or DRAM bytes out of range)");
    return t;
  } catch (const std::exception& e) {
    cache_.reject(k, e.what());
    return std::nullopt;
  }
}

void TrafficCache::store(const std::string& draw_key, const std::string& family, const CachedTraffic& t) const {
  json j = {{"absent", t.absent}};
  if (!t.absent) j["result"] = to_json(t.result);
  cache_.write(key(draw_key, family), j.dump() + "\n");
}

}  // namespace aovar::trace
