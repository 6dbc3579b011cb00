// aeroform-occt: OpenCASCADE's readers in a process of their own, started by Aeroform for each
// CAD file it reads through OpenCASCADE (libcore/cad/OcctProcess.h).
#include "cad/OcctProcess.h"

int main(int argc, char** argv) { return aero::cad::serveOcctRequest(argc, argv); }
