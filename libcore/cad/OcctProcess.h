#pragma once
// OpenCASCADE in a process of its own. Whatever of an IGES or STEP file OpenCASCADE reads (the
// IGES entities our own reader does not take, every STEP file) is read by a helper process,
// `aeroform-occt`, so that a crash or a hang inside OpenCASCADE on a damaged or hostile file ends
// as an InputError naming the file - not as the end of the application with the user's unsaved
// work, nor as a frozen window. Our own pre-checks (IgesText.h, StepText.h) refuse what they
// know to be fatal; this is the rest of the defence, for what nobody has found yet.
//
// The helper gets the request and writes its result as files of a private binary format (the
// same build writes and reads them, every double bit for bit), so a read gives the same patches
// in a helper as in this process. Where no helper exists (a library user without the
// applications, the fuzz targets, which must see OpenCASCADE's crashes themselves) OpenCASCADE
// runs in this process as before.
#include <atomic>
#include <string>

#include "common/Error.h"

namespace aero::cad {

enum class OcctIsolation {
    Process,    // in the helper process, when one is found (the default)
    InProcess,  // in this process (the fuzz targets; a helper's own work)
};

/// For the whole process; the default is Process.
void setOcctIsolation(OcctIsolation mode);
OcctIsolation occtIsolation();

/// The helper used: $AEROFORM_OCCT_HELPER when set ("none": no helper), else `aeroform-occt`
/// beside the running executable, else the one of the build tree this library was built in;
/// empty when none of them is an executable file (OpenCASCADE then runs in this process).
std::string occtHelperPath();

/// How long the helper may take for one file before it is stopped and the read fails:
/// $AEROFORM_CAD_TIME_LIMIT in seconds when set (0: no limit), else 600 s. Real files of a few
/// hundred faces take seconds; the limit is for a conversion that never ends.
double occtTimeLimit();

/// A read stopped by its OcctCancelScope's flag (an InputError, so callers that report bad input
/// report it too; the GUI tells it apart to say nothing more than that it was cancelled).
class OcctCancelled : public InputError {
  public:
    using InputError::InputError;
};

/// While a scope lives, a conversion that a read on this thread hands to the helper is stopped
/// soon after `*flag` becomes true (within about 20 ms: the helper is killed) and the read throws
/// OcctCancelled naming the file. So a window can read a file on a worker thread and offer a Cancel
/// button. Scopes nest (the innermost flag counts); a conversion in this process (no helper)
/// cannot be interrupted and does not look at the flag.
class OcctCancelScope {
  public:
    explicit OcctCancelScope(const std::atomic<bool>* flag);
    ~OcctCancelScope();
    OcctCancelScope(const OcctCancelScope&) = delete;
    OcctCancelScope& operator=(const OcctCancelScope&) = delete;

  private:
    const std::atomic<bool>* previous_;
};

/// The helper's main (`aeroform-occt REQUEST RESULT`): reads the request file, runs OpenCASCADE
/// in its own process and writes the result file. Returns the exit code (0 also when the
/// result is an error message for the caller).
int serveOcctRequest(int argc, char** argv);

}  // namespace aero::cad
