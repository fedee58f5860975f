#pragma once
/// Writing outputs so that a failure or an interruption never leaves a half-written file.

#include <filesystem>
#include <functional>

namespace glassmap {

/// Calls write(tmp) with a temporary path next to `target`, then renames tmp over target.
/// If write throws, the temporary is removed, target is left as it was, and the error rethrown.
/// The temporary keeps target's extension so that format-sniffing writers (GDAL) still work.
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& tmp)>& write);

/// Temporary sibling path for target: "<dir>/.<stem>.tmp<pid>-<n><ext>".
std::filesystem::path temporarySibling(const std::filesystem::path& target);

}  // namespace glassmap
