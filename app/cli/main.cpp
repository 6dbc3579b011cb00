#include <cstdlib>
#include <unistd.h>

#include "cli/Commands.h"

int main(int argc, char** argv) {
    // OpenMP threads that spin while they wait steal the cores the rest of the machine needs; on
    // a shared or oversubscribed 2-core machine that makes the flow solver many times slower.
    // The runtime reads OMP_WAIT_POLICY before main, so when the user has not chosen a policy
    // we choose "passive" and start again (once; an explicit setting is always respected).
    if (!std::getenv("OMP_WAIT_POLICY")) {
        setenv("OMP_WAIT_POLICY", "passive", 1);
        execv("/proc/self/exe", argv);  // returns only on failure: then run as we are
    }
    return aero::app::runCli(argc, argv);
}
