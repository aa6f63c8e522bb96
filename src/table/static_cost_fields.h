#pragma once
// The members of the "static" object by their JSON names, for its writer and both its readers
// (static_cost.cpp with nlohmann, json_reader.cpp with simdjson): one list, so they cannot disagree.
#include "table/static_cost.h"

namespace aovar::table::static_fields {

template <class Struct, class Member>
struct Field {
  const char* name;
  Member Struct::*member;
  bool required = false;  // absent optional members read as 0
};

// ProgramCounts: "fetches": {...}, the counts, "loops": {...}.
inline constexpr Field<FetchCounts, double> kFetches[] = {
    {"depth", &FetchCounts::depth},     {"normal", &FetchCounts::normal},   {"position", &FetchCounts::position},
    {"input", &FetchCounts::input},     {"history", &FetchCounts::history}, {"prefilter", &FetchCounts::prefilter}};
inline constexpr Field<ProgramCounts, double> kCounts[] = {
    {"alu", &ProgramCounts::alu, true},
    {"fma", &ProgramCounts::fma},
    {"div", &ProgramCounts::div},
    {"transcendental", &ProgramCounts::transcendental, true},
    {"cmp_select", &ProgramCounts::cmp_select},
    {"branches", &ProgramCounts::branches},
    {"unprojections", &ProgramCounts::unprojections},
    {"projections", &ProgramCounts::projections}};
inline constexpr Field<ProgramCounts, int> kLoops[] = {{"constant", &ProgramCounts::constant_loops},
                                                       {"dynamic", &ProgramCounts::dynamic_loops},
                                                       {"unrolled", &ProgramCounts::unrolled_loops}};
// ClassCounts ("weighted": {"ao": ..., "others": ...}).
inline constexpr Field<ClassCounts, double> kClasses[] = {
    {"fetches", &ClassCounts::fetches},   {"prefilter_fetches", &ClassCounts::prefilter_fetches},
    {"alu", &ClassCounts::alu},           {"transcendental", &ClassCounts::transcendental},
    {"div", &ClassCounts::div},           {"cmp_select", &ClassCounts::cmp_select},
    {"branches", &ClassCounts::branches}};
// StaticCost besides "ao", "passes" and "weighted" (all required but "weighted").
inline constexpr Field<StaticCost, double> kCost[] = {{"ao_bytes_per_pixel", &StaticCost::ao_bytes_per_pixel},
                                                      {"work_per_pixel", &StaticCost::work_per_pixel}};

}  // namespace aovar::table::static_fields
