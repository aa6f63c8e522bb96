#pragma once
// `aovar ship --shard k/n` and `--join` (issue 35): the screen, the one round that grows with the space, split
// over machines as sweep's shards are. Each shard profiles and fits as an unsharded run does (both are
// deterministic, and recorded in its OUT/ship.json), then screens its share of the candidates into
// OUT/screen (a sweep shard with its shard.json). The join takes the shards' folders: their fit, once its
// inputs match the join's, and their screens merged (sweep/merge.h checks them as one set), then eliminates,
// runs the survivors' round and selects on its own.
#include <filesystem>
#include <string>
#include <vector>

#include "table/table.h"
#include "variants/manifest.h"

namespace aovar::ship {

// OUT/ship.json: what a run's fit and screen were made from (hashes), so a re-run or a join can check them.
std::string recorded_input(const std::filesystem::path& out, const std::string& name);
void record_input(const std::filesystem::path& out, const std::string& name, const std::string& hash);

// OUT/calibration.json is checked as a cache entry would be (issue 54): ship.json records the fit's inputs (its
// key) and the hash of the file's text (its checksum). record_fit writes both for the file as it is now;
// fit_problem says why DIR's fit is not to be reused ("" when its recorded checksum matches; a missing file,
// another run's inputs, or a file edited, truncated or written by an earlier version without a checksum).
void record_fit(const std::filesystem::path& out, const std::string& fit_inputs);
std::string fit_problem(const std::filesystem::path& dir, const std::string& fit_inputs);

// Copies the calibration of the first shard folder whose fit has these inputs and is whole and within the
// manifest's ranges (calibrate::load_calibration) into `out` (with its record); a damaged one (fit_problem, or
// out of range) is passed over.
// Throws std::runtime_error (one line naming the folders, and why the last candidate was refused) when none has.
void adopt_shard_fit(const std::vector<std::filesystem::path>& shards, const std::string& fit_inputs,
                     const std::filesystem::path& out, const variants::Manifest& manifest);

struct JoinedScreen {
  table::CostTable table;
  int shards = 0;
  std::string balance;  // shard::balance_summary of the shards
};

// Before anything runs: the --join folders are folders of shard runs (each holds ship.json), and `out` is
// none of them and lies in none of them (util/output_apart.h). Throws std::runtime_error, one line.
void check_join_folders(const std::vector<std::filesystem::path>& shards, const std::filesystem::path& out);

// The shards' screens merged into `screen_out`/cost_table.json. Throws std::runtime_error (one line naming the
// shard) when one screened other inputs than `screen_inputs`, or when merge refuses the set (missing,
// duplicated, incomplete, foreign).
JoinedScreen join_screens(const std::vector<std::filesystem::path>& shards, const std::string& screen_inputs,
                          const std::filesystem::path& screen_out);

}  // namespace aovar::ship
