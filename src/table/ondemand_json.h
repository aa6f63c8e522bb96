#pragma once
// simdjson On-Demand values as aovar's types, for the cost table's reader (json_reader.cpp): each getter
// names what it reads in a one-line error ("time_ms.min is a string, not a number", or simdjson's word for a
// malformed value), and a field list is walked once in file order (On-Demand reads forward only).
#include <simdjson.h>

#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "table/detail.h"
#include "util/intervals.h"

namespace aovar::table::ondemand_json {
namespace od = simdjson::ondemand;
using nlohmann::json;

inline const char* type_name(od::value& v) {
  od::json_type t;
  if (v.type().get(t)) return "not valid JSON";
  switch (t) {
    case od::json_type::array: return "an array";
    case od::json_type::object: return "an object";
    case od::json_type::number: return "a number";
    case od::json_type::string: return "a string";
    case od::json_type::boolean: return "a boolean";
    case od::json_type::null: return "null";
  }
  return "unknown";
}

// A value that is not what `name` must be: its type, or simdjson's word for a malformed one.
[[noreturn]] inline void wrong(od::value& v, std::string_view name, const char* expected, simdjson::error_code e) {
  if (e == simdjson::INCORRECT_TYPE) throw std::runtime_error(fmt::format("{} is {}, not {}", name, type_name(v), expected));
  throw std::runtime_error(fmt::format("{}: {}", name, simdjson::error_message(e)));
}

inline bool is_null(od::value& v) {
  bool null = false;
  return !v.is_null().get(null) && null;
}
inline std::string text_of(od::value v, std::string_view name) {
  std::string_view s;
  if (auto e = v.get_string().get(s)) wrong(v, name, "a string", e);
  return std::string(s);
}
inline double number_of(od::value v, std::string_view name) {
  double d;
  if (auto e = v.get_double().get(d)) wrong(v, name, "a number", e);
  return d;
}
inline long long whole_of(od::value v, std::string_view name) {
  std::int64_t i;
  if (auto e = v.get_int64().get(i)) wrong(v, name, "a whole number", e);
  return i;
}
inline int int_of(od::value v, std::string_view name) {
  const long long i = whole_of(v, name);
  if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
    throw std::runtime_error(fmt::format("{} {} is out of range", name, i));
  return static_cast<int>(i);
}
inline bool bool_of(od::value v, std::string_view name) {
  bool b;
  if (auto e = v.get_bool().get(b)) wrong(v, name, "true or false", e);
  return b;
}
inline od::object object_of(od::value v, std::string_view name) {
  od::object o;
  if (auto e = v.get_object().get(o)) wrong(v, name, "an object", e);
  return o;
}
inline od::array array_of(od::value v, std::string_view name) {
  od::array a;
  if (auto e = v.get_array().get(a)) wrong(v, name, "an array", e);
  return a;
}
inline std::string_view key_of(simdjson::simdjson_result<od::field>& f) { return f.unescaped_key().value(); }

// A value as nlohmann::json, for the readers other files share.
inline json to_nlohmann(od::value v) {
  switch (v.type().value()) {
    case od::json_type::object: {
      json out = json::object();
      for (auto f : v.get_object()) {
        std::string key(key_of(f));  // before the value: On-Demand reads forward only
        out[key] = to_nlohmann(f.value().value());
      }
      return out;
    }
    case od::json_type::array: {
      json out = json::array();
      for (auto e : v.get_array()) out.push_back(to_nlohmann(e.value()));
      return out;
    }
    case od::json_type::number:
      switch (v.get_number_type().value()) {
        case od::number_type::signed_integer: return json(v.get_int64().value());
        case od::number_type::unsigned_integer: return json(v.get_uint64().value());
        case od::number_type::floating_point_number: break;
      }
      return json(v.get_double().value());
    case od::json_type::string: return json(std::string(v.get_string().value()));
    case od::json_type::boolean: return json(v.get_bool().value());
    case od::json_type::null: break;
  }
  if (!is_null(v)) throw std::runtime_error("not valid JSON");
  return json(nullptr);
}

inline util::Interval interval_of(od::value v, std::string_view name) {
  if (is_null(v)) return {};
  std::vector<double> ends;
  for (auto e : array_of(v, name)) ends.push_back(number_of(e.value(), name));
  if (ends.size() != 2) throw std::runtime_error(fmt::format("{}: {}", name, detail::kIntervalShape));
  return {ends[0], ends[1]};
}

inline std::vector<double> numbers_of(od::value v, std::string_view name) {
  std::vector<double> out;
  for (auto e : array_of(v, name)) out.push_back(number_of(e.value(), name));
  return out;
}

// Fields a row or one of its objects must have, by bit.
struct Required {
  std::uint32_t seen = 0;
  void check(std::span<const char* const> names, std::string_view parent) const {
    std::uint32_t bit = 1;
    for (const char* name : names) {
      if (!(seen & bit)) throw std::runtime_error(fmt::format("{}{}{} is missing", parent, parent.empty() ? "" : ".", name));
      bit <<= 1;
    }
  }
};

// Calls use(key, value) for each field of `v`, an object (`name` says what must be one).
template <class Use>
void each_field(od::value v, std::string_view name, Use&& use) {
  for (auto f : object_of(v, name)) {
    const std::string_view key = key_of(f);  // before the value: On-Demand reads forward only
    use(key, f.value().value());
  }
}

inline double nan_or_number(od::value x, std::string_view name) {
  return is_null(x) ? std::numeric_limits<double>::quiet_NaN() : number_of(x, name);
}

[[noreturn]] inline void missing(std::string_view path, std::string_view name) {
  throw std::runtime_error(fmt::format("{}.{} is missing", path, name));
}

}  // namespace aovar::table::ondemand_json
