#include "cli/Commands.h"

int main(int argc, char** argv) { return aero::app::runCli(argc, argv); }
