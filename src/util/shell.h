#pragma once
// Command lines aovar prints for the user to paste back into a shell (stress reproducers): every argument
// quoted for POSIX sh, so a path or key with spaces, quotes or $ survives the paste unchanged.
#include <string>
#include <string_view>

namespace aovar::util {

// `word` as one sh word: unchanged when it holds only characters no shell treats specially (letters,
// digits, and _ @ % + = : , . / -), else in single quotes with each ' written as '\''. Empty: ''.
std::string shell_quote(std::string_view word);

}  // namespace aovar::util
