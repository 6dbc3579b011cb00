// OpenCASCADE's readers in a helper process (see OcctProcess.h): the request and result files,
// starting and watching the helper, and the helper's side.
#include "cad/OcctProcess.h"

#include <spawn.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <utility>
#include <vector>

#include "cad/Occt.h"
#include "common/Error.h"

extern char** environ;

namespace aero::cad {

namespace {

thread_local const std::atomic<bool>* cancelFlag = nullptr;  // OcctCancelScope's

std::atomic<OcctIsolation> isolation{OcctIsolation::Process};

constexpr char kMagic[8] = {'A', 'E', 'R', 'O', 'O', 'C', 'C', 'T'};
constexpr std::uint32_t kFormatVersion = 2;
enum class Kind : std::uint32_t { Iges = 1, Step = 2 };
enum class Outcome : std::uint32_t { Ok = 0, Input = 1, Geometry = 2, Other = 3 };

// The files' format: the header (magic, version), then fixed-size values in this machine's
// representation and sized sequences (a 64-bit count, then the elements). Only the same build
// writes and reads them.
class Writer {
public:
    Writer() {
        raw(kMagic, sizeof kMagic);
        pod(kFormatVersion);
    }
    void raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
    template <class T>
    void pod(T v) {
        raw(&v, sizeof v);
    }
    void count(std::size_t n) { pod<std::uint64_t>(n); }
    void text(const std::string& s) {
        count(s.size());
        raw(s.data(), s.size());
    }
    template <class T>
    void values(const std::vector<T>& v) {
        count(v.size());
        if (!v.empty()) raw(v.data(), v.size() * sizeof(T));
    }
    const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
};

class Reader {
public:
    // `what` names the file in messages ("the OpenCASCADE helper's result").
    Reader(std::string bytes, std::string what) : bytes_(std::move(bytes)), what_(std::move(what)) {
        char magic[sizeof kMagic];
        raw(magic, sizeof magic);
        if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) throw InputError(what_ + " is not in the helper's format");
        if (pod<std::uint32_t>() != kFormatVersion) throw InputError(what_ + " is of another version of Aeroform");
    }
    void raw(void* p, std::size_t n) {
        if (n > bytes_.size() - at_) throw InputError(what_ + " is truncated");
        std::memcpy(p, bytes_.data() + at_, n);
        at_ += n;
    }
    template <class T>
    T pod() {
        T v;
        raw(&v, sizeof v);
        return v;
    }
    // A count of elements of `size` bytes each, checked against what is left.
    std::size_t count(std::size_t size) {
        const std::uint64_t n = pod<std::uint64_t>();
        if (n > (bytes_.size() - at_) / std::max<std::size_t>(size, 1)) throw InputError(what_ + " is truncated");
        return static_cast<std::size_t>(n);
    }
    std::string text() {
        std::string s(count(1), '\0');
        raw(s.data(), s.size());
        return s;
    }
    template <class T>
    std::vector<T> values() {
        std::vector<T> v(count(sizeof(T)));
        if (!v.empty()) raw(v.data(), v.size() * sizeof(T));
        return v;
    }
    bool done() const { return at_ == bytes_.size(); }

private:
    std::string bytes_;
    std::size_t at_ = 0;
    std::string what_;
};

// Each element of a sized sequence of structures takes at least this many bytes (for the count
// check before reserving).
constexpr std::size_t kMinElement = 8;

void put(Writer& w, const nurbs::Curve<double>& c) {
    w.pod<std::int32_t>(c.degree);
    w.values(c.knots);
    w.values(c.points);
    w.values(c.weights);
}
void get(Reader& r, nurbs::Curve<double>& c) {
    c.degree = r.pod<std::int32_t>();
    c.knots = r.values<double>();
    c.points = r.values<double>();
    c.weights = r.values<double>();
}
void put(Writer& w, const geometry::TrimLoop& loop) {
    w.count(loop.curves.size());
    for (const geometry::TrimCurve& c : loop.curves) {
        put(w, c.curve);
        w.pod(c.first);
        w.pod(c.last);
    }
}
void get(Reader& r, geometry::TrimLoop& loop) {
    loop.curves.resize(r.count(kMinElement));
    for (geometry::TrimCurve& c : loop.curves) {
        get(r, c.curve);
        c.first = r.pod<double>();
        c.last = r.pod<double>();
    }
}
void put(Writer& w, const occt::Face& f) {
    const geometry::Patch& p = f.patch;
    w.pod<std::int32_t>(p.degreeU);
    w.pod<std::int32_t>(p.degreeV);
    w.pod<std::int32_t>(p.countU);
    w.pod<std::int32_t>(p.countV);
    w.values(p.knotsU);
    w.values(p.knotsV);
    w.values(p.points);
    w.values(p.weights);
    put(w, f.trim.outer);
    w.count(f.trim.holes.size());
    for (const geometry::TrimLoop& h : f.trim.holes) put(w, h);
    w.text(f.surfaceType);
    w.pod<std::uint8_t>(f.converted ? 1 : 0);
    w.text(f.conversion);
    w.pod(f.trimDeviation);
    w.text(f.trimProblem);
    w.pod<std::int32_t>(f.stepId);
}
void get(Reader& r, occt::Face& f) {
    geometry::Patch& p = f.patch;
    p.degreeU = r.pod<std::int32_t>();
    p.degreeV = r.pod<std::int32_t>();
    p.countU = r.pod<std::int32_t>();
    p.countV = r.pod<std::int32_t>();
    p.knotsU = r.values<double>();
    p.knotsV = r.values<double>();
    p.points = r.values<double>();
    p.weights = r.values<double>();
    get(r, f.trim.outer);
    f.trim.holes.resize(r.count(kMinElement));
    for (geometry::TrimLoop& h : f.trim.holes) get(r, h);
    f.surfaceType = r.text();
    f.converted = r.pod<std::uint8_t>() != 0;
    f.conversion = r.text();
    f.trimDeviation = r.pod<double>();
    f.trimProblem = r.text();
    f.stepId = r.pod<std::int32_t>();
}
void put(Writer& w, const std::vector<occt::Face>& faces) {
    w.count(faces.size());
    for (const occt::Face& f : faces) put(w, f);
}
void get(Reader& r, std::vector<occt::Face>& faces) {
    faces.resize(r.count(kMinElement));
    for (occt::Face& f : faces) get(r, f);
}
void put(Writer& w, const std::vector<std::string>& lines) {
    w.count(lines.size());
    for (const std::string& s : lines) w.text(s);
}
void get(Reader& r, std::vector<std::string>& lines) {
    lines.resize(r.count(kMinElement));
    for (std::string& s : lines) s = r.text();
}

std::string readWhole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

bool writeWhole(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    return static_cast<bool>(out);
}

// A file of its own in the temporary directory, removed with the object.
class TempFile {
public:
    explicit TempFile(const char* role) {
        std::error_code ec;
        std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
        if (ec) dir = "/tmp";
        std::string pattern = (dir / (std::string("aeroform-occt-") + role + "-XXXXXX")).string();
        const int fd = ::mkstemp(pattern.data());
        if (fd < 0) {
            throw InputError("cannot create a temporary file in '" + dir.string() + "' for OpenCASCADE's helper: " +
                             std::strerror(errno));
        }
        ::close(fd);
        path_ = pattern;
    }
    ~TempFile() { ::unlink(path_.c_str()); }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

bool isExecutableFile(const std::string& p) {
    struct stat st {};
    return !p.empty() && ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
}

std::string seconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", s);
    return buf;
}

// Runs the helper on `request` and returns a reader positioned after an Ok outcome; throws the
// helper's error, or an InputError naming `path` (a `format` file) when the helper crashed, was
// stopped at the time limit or could not be started.
Reader runHelper(const std::string& helper, const Writer& request, const std::string& path, const char* format) {
    const std::string file = std::string(format) + " file '" + path + "'";
    TempFile requestFile("request"), resultFile("result");
    if (!writeWhole(requestFile.path(), request.bytes())) {
        throw InputError("cannot read " + file + ": cannot write the request for OpenCASCADE's helper to '" +
                         requestFile.path() + "'");
    }
    const double limit = occtTimeLimit();  // before the start: a bad setting must not leave a helper behind
    std::vector<std::string> args = {helper, requestFile.path(), resultFile.path()};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (const int rc = ::posix_spawn(&pid, helper.c_str(), nullptr, nullptr, argv.data(), environ); rc != 0) {
        throw InputError("cannot read " + file + ": cannot start OpenCASCADE's helper '" + helper + "': " +
                         std::strerror(rc) +
                         " (AEROFORM_OCCT_HELPER names the aeroform-occt program to use, or none to convert in this "
                         "process)");
    }
    const auto start = std::chrono::steady_clock::now();
    int status = 0;
    auto stopHelper = [&] {
        ::kill(pid, SIGKILL);
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
    };
    for (int waitMs = 1;;) {
        const pid_t w = ::waitpid(pid, &status, WNOHANG);
        if (w == pid) break;
        if (w < 0 && errno != EINTR) throw InputError("cannot read " + file + ": lost OpenCASCADE's helper process");
        if (cancelFlag && cancelFlag->load()) {
            stopHelper();
            throw OcctCancelled("reading " + file + " was cancelled (OpenCASCADE's helper was stopped)");
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (limit > 0 && elapsed > limit) {
            stopHelper();
            throw InputError("cannot read " + file + ": OpenCASCADE did not finish converting it in " + seconds(limit) +
                             " s and was stopped (the limit is AEROFORM_CAD_TIME_LIMIT, in seconds; 0 for none)");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(waitMs));
        waitMs = std::min(2 * waitMs, 20);
    }
    if (WIFSIGNALED(status)) {
        const char* name = ::sigdescr_np(WTERMSIG(status));  // thread-safe, unlike strsignal
        throw InputError("cannot read " + file + ": OpenCASCADE crashed converting it (" +
                         (name ? std::string(name) : "signal " + std::to_string(WTERMSIG(status))) +
                         ", in its helper process, so nothing else was affected): the file is damaged or holds an "
                         "entity OpenCASCADE cannot convert");
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        throw InputError("cannot read " + file + ": OpenCASCADE's helper '" + helper + "' failed (exit status " +
                         std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    }
    Reader result(readWhole(resultFile.path()), "the result of OpenCASCADE's helper for " + file);
    const auto outcome = static_cast<Outcome>(result.pod<std::uint32_t>());
    if (outcome == Outcome::Ok) return result;
    const std::string message = result.text();
    if (outcome == Outcome::Input) throw InputError(message);
    if (outcome == Outcome::Geometry) throw GeometryError(message);
    throw Error(message);
}

// A request of `kind` from this process (its id: the helper ends if its parent is another,
// i.e. this process ended before the helper could tie its life to it).
Writer newRequest(Kind kind) {
    Writer w;
    w.pod(kind);
    w.pod<std::int64_t>(::getpid());
    return w;
}

std::string helperForThisCall() {
    return occtIsolation() == OcctIsolation::Process ? occtHelperPath() : std::string();
}

}  // namespace

OcctCancelScope::OcctCancelScope(const std::atomic<bool>* flag) : previous_(cancelFlag) { cancelFlag = flag; }
OcctCancelScope::~OcctCancelScope() { cancelFlag = previous_; }

void setOcctIsolation(OcctIsolation mode) { isolation = mode; }
OcctIsolation occtIsolation() { return isolation; }

std::string occtHelperPath() {
    if (const char* env = std::getenv("AEROFORM_OCCT_HELPER"); env && *env) {
        return std::strcmp(env, "none") == 0 ? std::string() : std::string(env);  // as the user says
    }
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::string beside = (self.parent_path() / "aeroform-occt").string();
        if (isExecutableFile(beside)) return beside;
    }
#ifdef AEROFORM_OCCT_HELPER_BUILD_PATH
    if (isExecutableFile(AEROFORM_OCCT_HELPER_BUILD_PATH)) return AEROFORM_OCCT_HELPER_BUILD_PATH;
#endif
    return {};
}

double occtTimeLimit() {
    if (const char* env = std::getenv("AEROFORM_CAD_TIME_LIMIT"); env && *env) {
        char* end = nullptr;
        const double s = std::strtod(env, &end);
        if (end != env && *end == '\0' && s >= 0 && std::isfinite(s)) return s;
        throw InputError(std::string("AEROFORM_CAD_TIME_LIMIT is '") + env +
                         "': not a number of seconds (0 or more; 0 for no limit)");
    }
    return 600;
}

namespace occt {

std::vector<EntityFaces> transferIgesEntitiesIsolated(const std::string& path, const std::string& occtUnit,
                                                      const std::vector<int>& directoryEntries,
                                                      const std::vector<char>& projectEdges) {
    const std::string helper = helperForThisCall();
    if (helper.empty()) return transferIgesEntities(path, occtUnit, directoryEntries, projectEdges);
    Writer request = newRequest(Kind::Iges);
    request.text(path);
    request.text(occtUnit);
    request.values(directoryEntries);
    request.values(projectEdges);
    Reader r = runHelper(helper, request, path, "IGES");
    std::vector<EntityFaces> out(r.count(kMinElement));
    for (EntityFaces& e : out) {
        get(r, e.faces);
        e.failure = r.text();
    }
    return out;
}

StepFile readStepIsolated(const std::string& path) {
    const std::string helper = helperForThisCall();
    if (helper.empty()) return readStep(path);
    Writer request = newRequest(Kind::Step);
    request.text(path);
    Reader r = runHelper(helper, request, path, "STEP");
    StepFile out;
    get(r, out.faces);
    out.unit = r.text();
    out.unitName = r.text();
    get(r, out.notes);
    get(r, out.warnings);
    out.roots = r.pod<std::int32_t>();
    return out;
}

}  // namespace occt

int serveOcctRequest(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: aeroform-occt REQUEST RESULT\n"
                             "Reads a CAD file with OpenCASCADE for Aeroform, in a process of its own; "
                             "Aeroform runs it, not a user.\n");
        return 2;
    }
    // Ends with the application that started it (a conversion that never ends would outlive a
    // killed application otherwise).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    setOcctIsolation(OcctIsolation::InProcess);
    Writer out;
    try {
        Reader request(readWhole(argv[1]), std::string("the request '") + argv[1] + "'");
        const auto kind = static_cast<Kind>(request.pod<std::uint32_t>());
        // The application ended before prctl above took effect: nobody waits for the result.
        if (request.pod<std::int64_t>() != static_cast<std::int64_t>(::getppid())) return 3;
        if (kind == Kind::Iges) {
            const std::string path = request.text();
            const std::string unit = request.text();
            const std::vector<int> entities = request.values<int>();
            const std::vector<char> project = request.values<char>();
            const std::vector<occt::EntityFaces> faces = occt::transferIgesEntities(path, unit, entities, project);
            out.pod(Outcome::Ok);
            out.count(faces.size());
            for (const occt::EntityFaces& e : faces) {
                put(out, e.faces);
                out.text(e.failure);
            }
        } else if (kind == Kind::Step) {
            const occt::StepFile file = occt::readStep(request.text());
            out.pod(Outcome::Ok);
            put(out, file.faces);
            out.text(file.unit);
            out.text(file.unitName);
            put(out, file.notes);
            put(out, file.warnings);
            out.pod<std::int32_t>(file.roots);
        } else {
            throw InputError(std::string("the request '") + argv[1] + "' asks for an unknown kind of file");
        }
    } catch (const std::exception& e) {
        out = Writer();
        const Outcome o = dynamic_cast<const InputError*>(&e)      ? Outcome::Input
                          : dynamic_cast<const GeometryError*>(&e) ? Outcome::Geometry
                                                                   : Outcome::Other;
        out.pod(o);
        out.text(e.what());
    }
    if (!writeWhole(argv[2], out.bytes())) {
        std::fprintf(stderr, "aeroform-occt: cannot write the result '%s': %s\n", argv[2], std::strerror(errno));
        return 4;
    }
    return 0;
}

}  // namespace aero::cad
