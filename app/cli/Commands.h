#pragma once
// The subcommands of aeroform-cli. Each takes its own arguments (after the subcommand name),
// writes human output to stderr or machine output (--json) to stdout, and returns the
// process exit code: 0 success, 1 failure of the work (bad input, invalid geometry),
// 2 usage error. Exceptions from libcore are caught here, at the boundary.
#include <string>

namespace aero::app {

/// Dispatches argv[1] (the subcommand); argv[0] is the program name.
int runCli(int argc, char** argv);

/// OpenMP threads that spin while they wait steal the cores the rest of the machine needs; on a
/// shared or oversubscribed 2-core machine that makes the flow solver many times slower. The
/// runtime reads OMP_WAIT_POLICY before main, so when the user has not chosen a policy this sets
/// "passive" (with a short spin, GOMP_SPINCOUNT 3000, unless the user set one) and executes the
/// program again with the same arguments (once; an explicit setting is always respected).
/// Returns only when no restart was needed or it failed.
void ensurePassiveOpenMpWaiting(char** argv);

/// Headless run of a case or geometry file (what `aeroform --batch FILE` does).
int runBatch(const std::string& path);

}  // namespace aero::app
