// OpenCASCADE's readers in their helper process (cad/OcctProcess.h): the same patches, trims and
// report to the bit as in this process, and a helper that crashes, hangs, fails or answers
// garbage is an InputError naming the file - the calling process lives on.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include "cad/Iges.h"
#include "cad/OcctProcess.h"
#include "cad/Step.h"
#include "common/Error.h"

namespace {

using namespace aero;
namespace fs = std::filesystem;

const std::string kCorpus = AEROFORM_FUZZ_CORPUS_DIR;

// Sets an environment variable for the scope, and puts back what was there.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (old_) {
            ::setenv(name_, old_->c_str(), 1);
        } else {
            ::unsetenv(name_);
        }
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

geometry::PatchSet readCad(const std::string& path, cad::ReadReport& report) {
    return path.ends_with(".stp") ? cad::readStep(path, &report) : cad::readIges(path, &report);
}

void expectSameTrimLoop(const geometry::TrimLoop& a, const geometry::TrimLoop& b) {
    ASSERT_EQ(a.curves.size(), b.curves.size());
    for (std::size_t c = 0; c < a.curves.size(); ++c) {
        EXPECT_EQ(a.curves[c].curve.degree, b.curves[c].curve.degree);
        EXPECT_EQ(a.curves[c].curve.knots, b.curves[c].curve.knots);
        EXPECT_EQ(a.curves[c].curve.points, b.curves[c].curve.points);
        EXPECT_EQ(a.curves[c].curve.weights, b.curves[c].curve.weights);
        EXPECT_EQ(a.curves[c].first, b.curves[c].first);
        EXPECT_EQ(a.curves[c].last, b.curves[c].last);
    }
}

// Files that OpenCASCADE converts (surfaces of revolution, trimmed faces, model-space trims, a
// unit other than mm), written by OpenCASCADE and by hand.
TEST(OcctProcess, TheHelperReadsWhatThisProcessReadsToTheBit) {
    ASSERT_FALSE(cad::occtHelperPath().empty()) << "aeroform-occt is not built beside the applications";
    const char* files[] = {"iges/occt_revolution_m.igs", "iges/occt_trimmed.igs",  "iges/occt_model_space_trims.igs",
                           "iges/occt_in_back.igs",      "iges/hand_wing_m.igs",   "step/occt_trimmed.stp",
                           "step/inch.stp",              "step/trimmed.stp"};
    for (const char* name : files) {
        SCOPED_TRACE(name);
        const std::string path = kCorpus + "/" + name;
        cad::ReadReport here, there;
        cad::setOcctIsolation(cad::OcctIsolation::InProcess);
        const geometry::PatchSet a = readCad(path, here);
        cad::setOcctIsolation(cad::OcctIsolation::Process);
        const geometry::PatchSet b = readCad(path, there);
        ASSERT_GT(a.size(), 0);
        ASSERT_EQ(a.size(), b.size());
        EXPECT_EQ(a.unit, b.unit);
        EXPECT_EQ(a.names, b.names);
        for (int k = 0; k < a.size(); ++k) {
            const geometry::Patch &p = a.patches[k], &q = b.patches[k];
            EXPECT_EQ(p.degreeU, q.degreeU);
            EXPECT_EQ(p.degreeV, q.degreeV);
            EXPECT_EQ(p.countU, q.countU);
            EXPECT_EQ(p.countV, q.countV);
            EXPECT_EQ(p.knotsU, q.knotsU);
            EXPECT_EQ(p.knotsV, q.knotsV);
            EXPECT_EQ(p.points, q.points);
            EXPECT_EQ(p.weights, q.weights);
            expectSameTrimLoop(a.trims[k].outer, b.trims[k].outer);
            ASSERT_EQ(a.trims[k].holes.size(), b.trims[k].holes.size());
            for (std::size_t h = 0; h < a.trims[k].holes.size(); ++h) expectSameTrimLoop(a.trims[k].holes[h], b.trims[k].holes[h]);
        }
        EXPECT_EQ(here.warnings, there.warnings);
        EXPECT_EQ(here.notes, there.notes);
        EXPECT_EQ(here.unitSource, there.unitSource);
        ASSERT_EQ(here.items.size(), there.items.size());
        for (std::size_t i = 0; i < here.items.size(); ++i) {
            EXPECT_EQ(here.items[i].entity, there.items[i].entity);
            EXPECT_EQ(here.items[i].surface, there.items[i].surface);
            EXPECT_EQ(here.items[i].trim, there.items[i].trim);
            EXPECT_EQ(here.items[i].patches, there.items[i].patches);
            EXPECT_EQ(here.items[i].note, there.items[i].note);
        }
    }
}

// Stand-ins for a helper that crashes, hangs, fails or writes garbage: whatever it does, the read
// fails with an InputError that names the file and says what happened, within the time limit.
TEST(OcctProcess, AHelperThatCrashesHangsOrFailsIsAnErrorNamingTheFile) {
    const fs::path dir = fs::path(AEROFORM_TEST_OUTPUT_DIR) / "occt_process";
    fs::create_directories(dir);
    auto script = [&](const std::string& name, const std::string& body) {
        const fs::path p = dir / name;
        std::ofstream(p) << "#!/bin/sh\n" << body << "\n";
        fs::permissions(p, fs::perms::owner_all);
        return p.string();
    };
    const std::string crash = script("crash.sh", "kill -SEGV $$");
    const std::string hang = script("hang.sh", "exec sleep 60");
    const std::string garbage = script("garbage.sh", "echo 'not a result' > \"$2\"");
    const std::string fails = script("fails.sh", "exit 7");
    const std::string step = kCorpus + "/step/occt_trimmed.stp";
    const std::string iges = kCorpus + "/iges/occt_revolution_m.igs";
    ScopedEnv limit("AEROFORM_CAD_TIME_LIMIT", "1");
    const fs::path tmp = dir / "tmp";  // the request and result files go here
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    ScopedEnv tmpdir("TMPDIR", tmp.string());
    auto failure = [&](const std::string& helper, const std::string& file) {
        ScopedEnv use("AEROFORM_OCCT_HELPER", helper);
        EXPECT_EQ(cad::occtHelperPath(), helper);
        cad::ReadReport report;
        try {
            readCad(file, report);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        ADD_FAILURE() << "no error with the helper " << helper;
        return std::string();
    };
    std::string m = failure(crash, step);
    EXPECT_NE(m.find("STEP file '" + step + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("OpenCASCADE crashed"), std::string::npos) << m;
    EXPECT_NE(m.find("Segmentation fault"), std::string::npos) << m;
    m = failure(crash, iges);
    EXPECT_NE(m.find("IGES file '" + iges + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("OpenCASCADE crashed"), std::string::npos) << m;
    const auto t0 = std::chrono::steady_clock::now();
    m = failure(hang, step);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_NE(m.find("did not finish converting it in 1 s"), std::string::npos) << m;
    EXPECT_NE(m.find("AEROFORM_CAD_TIME_LIMIT"), std::string::npos) << m;
    EXPECT_LT(took, 30.0);  // stopped at the limit, not after the helper's 60 s
    m = failure(garbage, step);
    EXPECT_NE(m.find("not in the helper's format"), std::string::npos) << m;
    m = failure(fails, step);
    EXPECT_NE(m.find("failed (exit status 7)"), std::string::npos) << m;
    m = failure((dir / "missing").string(), step);
    EXPECT_NE(m.find("cannot start OpenCASCADE's helper"), std::string::npos) << m;
    // "none": OpenCASCADE in this process.
    {
        ScopedEnv none("AEROFORM_OCCT_HELPER", "none");
        EXPECT_EQ(cad::occtHelperPath(), "");
        cad::ReadReport report;
        EXPECT_GT(cad::readStep(step, &report).size(), 0);
    }
    {
        ScopedEnv bad("AEROFORM_CAD_TIME_LIMIT", "soon");
        EXPECT_THROW(cad::occtTimeLimit(), InputError);
    }
    // Cancelled from another thread (the GUI's Cancel button): the hanging helper is stopped
    // soon after the flag is set, long before the time limit, and the read says so.
    {
        std::atomic<bool> cancel{false};
        std::string what;
        double waited = 0;
        {
            ScopedEnv use("AEROFORM_OCCT_HELPER", hang);
            ScopedEnv noLimit("AEROFORM_CAD_TIME_LIMIT", "0");
            std::thread canceller([&] {
                std::this_thread::sleep_for(std::chrono::milliseconds(300));
                cancel = true;
            });
            const auto c0 = std::chrono::steady_clock::now();
            {
                const cad::OcctCancelScope scope(&cancel);
                cad::ReadReport report;
                try {
                    readCad(step, report);
                } catch (const cad::OcctCancelled& e) {
                    what = e.what();
                }
            }
            waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
            canceller.join();
        }
        EXPECT_NE(what.find("reading STEP file '" + step + "' was cancelled"), std::string::npos) << what;
        EXPECT_GE(waited, 0.29);
        EXPECT_LT(waited, 20.0);  // not the helper's 60 s
        // Outside the scope the flag, still set, stops nothing: the real helper reads the file.
        ASSERT_FALSE(cad::occtHelperPath().empty());
        cad::ReadReport report;
        EXPECT_GT(readCad(step, report).size(), 0);
    }
    // No request or result file left behind, whatever happened to the helper.
    EXPECT_EQ(fs::temp_directory_path(), tmp);
    for (const auto& entry : fs::directory_iterator(tmp)) ADD_FAILURE() << "left behind: " << entry.path();
}

}  // namespace
