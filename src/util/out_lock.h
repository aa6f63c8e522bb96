#pragma once
// One writer per output folder. Two runs into one --out interleave their files (a sweep's rows lost, a
// generate's folder matching neither selection), so every command that writes an output folder holds an
// exclusive flock(2) on OUT/.aovar.lock while it runs; a second one is refused, naming the lock. The kernel
// releases the lock when the process exits or is killed, so a killed run never leaves a stale lock and
// kill-anywhere resumption keeps working. The lock file stays (empty), except that a run which made the
// folder and wrote nothing into it (it failed) removes both again: "when anything fails, nothing is
// written". A process that locked the file just as it was removed sees it unnamed and locks the new one.
//
// Symbolic links inside an output folder are refused when the lock is taken, naming the link: every writer
// writes below the folder it was given (and `report` embeds only what resolves there), so a link such as
// OUT/measure -> /elsewhere would send profile.json, measure.json and images out of it. The folder itself
// may be a link (it is what the user named); aovar never makes links.
//
// Forked children (stress slices, util::run_isolated) close their copy of the descriptor right after fork
// (pthread_atfork): the lock is the parent's alone, so a parent killed mid-run frees the folder at once even
// while an orphaned child still renders.
#include <filesystem>

#include <sys/types.h>

namespace aovar::util {

inline constexpr const char* kLockFileName = ".aovar.lock";

class OutputLock {
 public:
  // Creates `folder` when missing, then takes the lock. Throws std::runtime_error "<folder>/.aovar.lock:
  // error: another aovar is writing into <folder> ..." when another process (or another OutputLock) holds it,
  // and "<link>: error: a symbolic link inside the output folder ..." for the first link below `folder` when
  // `refuse_links` (false for the folder of a one-file output: a rename replaces a link, never follows it).
  explicit OutputLock(const std::filesystem::path& folder, bool refuse_links = true);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path folder_, path_;
  bool created_folder_ = false;  // this lock made the folder: removed again if nothing else was put there
  int fd_ = -1;
  pid_t owner_ = -1;  // the process that took it: a forked copy of this object closes nothing
};

}  // namespace aovar::util
