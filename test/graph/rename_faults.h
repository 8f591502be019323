// The test binary's own rename() and renameat2(), which the libraries' calls reach first: they count the
// renames and can kill the process at the n-th, as a power cut or SIGKILL would stop a save there.
#pragma once

namespace scan_context_loop {
namespace test {

/// From now on the n-th rename (counted from this call; 0: never) kills the process with SIGKILL.
void killAtRename(int n);
/// Renames since the last killAtRename().
int renamesSeen();

}  // namespace test
}  // namespace scan_context_loop
