#include "cli/Commands.h"

int main(int argc, char** argv) {
    aero::app::ensurePassiveOpenMpWaiting(argv);
    return aero::app::runCli(argc, argv);
}
