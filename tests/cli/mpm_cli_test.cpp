// `suite mpm` end to end on small grids (box:6,6,6 and box:8,8,8, well under a second a run): the
// files of a run, read back by meshio (tests/check_mpm_vtu.py); the same particles in the same
// places whatever the grid's and the particles' order; every bad input one line, exit 2 and no
// directory; --dry-run writes nothing; a run forced past the stable step exits 1; an implicit run's
// Newton recorded, and a failed one exits 3; an interrupted run keeps its files and exits 128+signal.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite::test;

namespace {

const std::string checker = std::string(SUITE_SOURCE_DIR) + "/tests/check_mpm_vtu.py";

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

std::size_t count_lines(const std::string& text) {
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// A small run into `dir`, checked to succeed.
void small_run(const std::string& dir, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"mpm", "--mesh=box:6,6,6", "--steps=40", "--vtk-every=20", "--out=" + dir};
    args.insert(args.end(), extra.begin(), extra.end());
    const Outcome r = run_suite(args, 120);
    ASSERT_EQ(r.status, 0) << join(args) << "\n" << describe(r);
}

}  // namespace

TEST(MpmCli, SmallRunWritesSnapshotsCsvJsonAndPngThatMeshioReadsBack) {
    TempDir tmp;
    const std::string dir = tmp.file("dam");
    const Outcome r = run_suite(
        {"mpm", "--case=dam-collapse", "--mesh=box:6,6,6", "--steps=40", "--vtk-every=20", "--out=" + dir}, 120);
    ASSERT_EQ(r.status, 0) << describe(r);
    for (const char* name : {"particles_000000.vtu", "particles_000020.vtu", "particles_000040.vtu", "particles.pvd",
                             "front.csv", "mpm.json"})
        EXPECT_TRUE(fs::is_regular_file(dir + "/" + name)) << name;
    EXPECT_FALSE(fs::exists(dir + "/particles_000010.vtu"));
    // front.csv: a header and one row a step from step 0.
    const std::string csv = slurp(dir + "/front.csv");
    EXPECT_EQ(csv.rfind("step,time,front,kinetic_energy,dt,potential_energy,internal_energy,mean_curve_gap,same_"
                        "element,top_settlement,reordered,stepping_seconds\n",
                        0),
              0u)
        << csv;
    EXPECT_EQ(count_lines(csv), 1u + 41u);
    // The PNG: there, a PNG, not empty.
    const std::string png = slurp(dir + "/front.png");
    ASSERT_GT(png.size(), 1000u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    // mpm.json: the counts, the checks passed, complete.
    const nlohmann::json doc = read_json(dir + "/mpm.json");
    EXPECT_EQ(doc["complete"], true);
    EXPECT_EQ(doc["steps"], 40);
    EXPECT_EQ(doc["verification"]["passed"], true);
    EXPECT_EQ(doc["verification"]["checks"].size(), 4u);
    EXPECT_GT(doc["counts"]["particles"].get<std::size_t>(), 0u);
    EXPECT_EQ(doc["counts"]["elements"], 6 * 6 * 6 * 6);
    EXPECT_EQ(doc["counts"]["nodes"], 7 * 7 * 7);
    EXPECT_EQ(doc["mass"]["drift_relative"], 0.0);
    EXPECT_LE(doc["mass"]["nodal_error_relative"].get<double>(), 1e-12);
    EXPECT_EQ(doc["files"]["png"], "front.png");
    EXPECT_EQ(doc["snapshots"].size(), 3u);
    // The summary on stdout names what the brief asks for; the progress lines (stderr is a
    // pipe here) come every tenth of the run.
    for (const char* word :
         {"particles", "grid", "dt", "steps", "wall", "per thread", "front", "mass drift", "clamped", "NaN check"})
        EXPECT_NE(r.out.find(word), std::string::npos) << word << "\n" << r.out;
    EXPECT_NE(r.out.find(std::to_string(doc["counts"]["particles"].get<std::size_t>())), std::string::npos) << r.out;
    EXPECT_EQ(count_lines(r.err), 10u) << r.err;
    EXPECT_NE(r.err.find("step 40/40"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/.suite.lock")) << "the directory's lock is released at the end";
    // Every .vtu read back by meshio: the particle count of mpm.json, ids a permutation.
    const Outcome py = run_program({SUITE_PYTHON, checker, dir}, 120);
    if (py.status == 3) GTEST_SKIP() << py.out;
    EXPECT_EQ(py.status, 0) << describe(py);
}

TEST(MpmCli, HilbertGridAndSortedParticlesEndWhereNaturalAndUnsortedDo) {
    TempDir tmp;
    const std::string a = tmp.file("natural"), b = tmp.file("hilbert"), c = tmp.file("dynamic");
    small_run(a, {"--no-png", "--quiet"});
    small_run(b, {"--ordering=hilbert", "--particles=sorted", "--sort-every=7", "--no-png", "--quiet"});
    small_run(c, {"--ordering=morton", "--particles=dynamic", "--sort-every=5", "--threads=2", "--no-png", "--quiet"});
    for (const auto& other : {b, c}) {
        const Outcome py = run_program({SUITE_PYTHON, checker, a, other}, 120);
        if (py.status == 3) GTEST_SKIP() << py.out;
        EXPECT_EQ(py.status, 0) << other << "\n" << describe(py);
    }
}

TEST(MpmCli, QuietPrintsNothingAndNoSnapshotsWithVtkEveryZero) {
    TempDir tmp;
    const std::string dir = tmp.file("q");
    const Outcome r =
        run_suite({"mpm", "--mesh=box:6,6,6", "--steps=5", "--vtk-every=0", "--no-png", "--quiet", "--out=" + dir}, 60);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err, "");
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{".suite-files", "front.csv", "mpm.json"}))
        << "the run's files and their manifest";
    EXPECT_EQ(slurp(dir + "/.suite-files"), "suite mpm\nfront.csv\nmpm.json\n");
    EXPECT_TRUE(read_json(dir + "/mpm.json")["files"]["collection"].is_null());
}

TEST(MpmCli, BadInputIsOneLineExitTwoAndNoDirectory) {
    TempDir tmp;
    const std::string dir = tmp.file("dam");
    const auto refused = [&](const std::vector<std::string>& extra, const std::string& expected, bool with_out = true) {
        // A small grid and run, unless the case gives its own --mesh or --steps.
        std::vector<std::string> args = {"mpm"};
        for (const std::string base : {"--mesh=box:6,6,6", "--steps=10"}) {
            const std::string name = base.substr(0, base.find('=') + 1);
            if (std::none_of(extra.begin(), extra.end(), [&](const std::string& e) { return e.rfind(name, 0) == 0; }))
                args.push_back(base);
        }
        if (with_out) args.push_back("--out=" + dir);
        args.insert(args.end(), extra.begin(), extra.end());
        const Outcome r = run_suite(args, 60);
        EXPECT_EQ(r.status, 2) << join(args) << "\n" << describe(r);
        EXPECT_EQ(count_lines(r.err), 1u) << describe(r);
        EXPECT_EQ(r.err.rfind("suite: error: ", 0), 0u) << describe(r);
        EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr lacks \"" << expected << "\"\n" << describe(r);
        EXPECT_TRUE(r.out.empty()) << describe(r);
        EXPECT_FALSE(fs::exists(dir)) << join(args);
    };
    refused(
        {"--case=dambreak"},
        "unknown case 'dambreak' (did you mean 'dam-break'?); accepted: dam-collapse, dam-break, column, free-fall");
    refused({"--case=dam-break", "--column=0.3,1,0.6"},
            "--column does not apply to --case=dam-break (a fluid: it takes --sound-speed, --viscosity and --density)");
    refused({"--case=dam-break", "--young=1e6"}, "--young does not apply to --case=dam-break");
    refused({"--case=column", "--sound-speed=40"}, "--sound-speed does not apply to --case=column (an elastic solid");
    refused(
        {"--case=column", "--column=0.5,1,0.5"},
        "--column=0.5,1,0.5 with --case=column: the one-dimensional answer needs the layer to fill the box's width");
    refused({"--particles=unsorted"},
            "unknown particle order 'unsorted' (now called 'shuffled'); accepted: seeded, shuffled, sorted, dynamic");
    refused({"--case=dam-break", "--sound-speed=0"}, "--sound-speed=0: the fluid's sound speed must be > 0 (m/s)");
    refused({"--case=dam-break", "--viscosity=-1"},
            "--viscosity=-1: the fluid's dynamic viscosity is a number of Pa s from 0 to 1e30");
    refused({"--poisson=0.5"}, "--poisson=0.5: Poisson's ratio must lie in (-1, 0.5)");
    refused({"--young=0"}, "--young=0: Young's modulus E must be > 0");
    refused({"--young=1e5x"}, "--young=1e5x: expected a finite number");
    refused({"--density=nan"}, "--density=nan: expected a finite number");
    refused({"--ppe=0"}, "--ppe=0: expected a whole number from 1 to 1000");
    refused({"--column=0.4,0.4,1.5"},
            "--column=0.4,0.4,1.5: the material's region [0,0,0] to [0.4,0.4,1.5] is not a box inside the grid's box");
    refused({"--column=0.4,0.4"}, "--column=0.4,0.4: the material's region [0,X]x[0,Y]x[0,Z] is three finite numbers");
    refused({"--column=0.01,0.01,0.01"}, "--column=0.01,0.01,0.01: the material's region holds no element's centroid");
    refused({"--mesh=disk:refine=2"}, "--mesh=disk:refine=2: the MPM background grid must be made of tetrahedra");
    refused({"--dt=1"}, "--dt=1: above the stable time step");
    refused({"--dt=-0.001"}, "--dt=-0.001: the time step is a number of seconds >= 0");
    refused({"--courant=1.5"}, "--courant=1.5: the Courant number must lie in (0, 1]");
    refused({"--steps=-1"}, "--steps=-1: expected a whole number from 0 to 1000000000");
    refused({"--vtk-every=2.5"}, "--vtk-every=2.5: expected a whole number");
    refused({"--sort-every=x"}, "--sort-every=x: expected a whole number");
    refused({"--threads=0"}, "--threads=0: expected a whole number from 1 to 1024");
    refused({"--threads=65"},
            "--threads=65: the partition strategy (the default for more than one thread) takes at most 64 threads");
    refused({"--ordering=hilbrt"},
            "unknown ordering 'hilbrt' (did you mean 'hilbert'?); accepted: natural, random, morton, hilbert");
    refused({"--particles=sortd"},
            "unknown particle order 'sortd' (did you mean 'sorted'?); accepted: seeded, shuffled, sorted, dynamic");
    refused({"--strategy=locks"}, "unknown strategy 'locks'; accepted: serial, atomic, colour, partition");
    refused({"--seed=-3"}, "--seed=-3: expected a whole number");
    refused({"--young="}, "--young= has an empty value");
    refused({"--vtk-evry=5"}, "unknown option '--vtk-evry' (did you mean '--vtk-every'?)");
    refused({"--integrator=newmark"}, "unknown integrator 'newmark'; accepted: explicit, implicit, static");
    refused({"--integrator=implicit", "--case=dam-break"},
            "--integrator=implicit: the implicit integrators have the elastic material only");
    refused({"--integrator=implicit", "--newmark=0.2,0.5"},
            "--newmark=0.2,0.5: Newmark's β, γ must satisfy 1/2 <= γ <= 2β <= 1");
    refused({"--integrator=implicit", "--newmark=0.25"}, "--newmark=0.25: Newmark's BETA,GAMMA, two numbers");
    refused({"--integrator=static", "--newmark=0.3,0.5"},
            "--newmark applies to --integrator=implicit (static has no inertia)");
    refused({"--solver=cholmod"}, "--solver applies to --integrator=implicit or static, not explicit");
    refused({"--newton-max=3"}, "--newton-max applies to --integrator=implicit or static, not explicit");
    refused({"--integrator=implicit", "--newton-max=0"}, "--newton-max=0: expected a whole number from 1 to 1000");
    refused({"--integrator=implicit", "--solver=lu"}, "unknown linear solver 'lu'; accepted: cg, cholmod");
    refused({"--integrator=implicit", "--strain=tiny"}, "unknown --strain 'tiny'; accepted: large, small");
    refused({"--integrator=implicit", "--courant=0.5"}, "--courant applies to --integrator=explicit");
    refused({"--integrator=implicit", "--damping=1"}, "--damping applies to --integrator=explicit");
    refused({}, "suite mpm needs --out=DIR", false);
    refused({"--out=" + tmp.file("no/such/parent")}, "does not exist", false);
}

TEST(MpmCli, AnImplicitRunRecordsItsNewtonAndAFailedNewtonExitsThree) {
    TempDir tmp;
    const std::string dir = tmp.file("implicit");
    const Outcome r = run_suite(
        {"mpm", "--integrator=implicit", "--mesh=box:6,6,6", "--steps=8", "--vtk-every=0", "--no-png", "--out=" + dir},
        120);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("integrator     implicit, large strain, cg"), std::string::npos) << r.out;
    const nlohmann::json doc = read_json(dir + "/mpm.json");
    EXPECT_EQ(doc["settings"]["integrator"], "implicit");
    EXPECT_EQ(doc["settings"]["newmark"], nlohmann::json::array({0.25, 0.5}));
    EXPECT_GE(doc["implicit"]["newton_iterations"].get<int>(), 8) << doc["implicit"];
    EXPECT_GT(doc["implicit"]["cg_iterations"].get<int>(), 0);
    EXPECT_LT(doc["implicit"]["worst_final_residual"].get<double>(), 1e-8);
    // 10 times the explicit stable step, the default.
    EXPECT_NEAR(doc["dt"].get<double>() / doc["stable_dt"].get<double>(), 10, 1e-9);
    std::vector<std::string> checks;
    for (const auto& c : doc["verification"]["checks"]) {
        checks.push_back(c["check"]);
        EXPECT_TRUE(c["passed"].get<bool>()) << c;
    }
    EXPECT_NE(std::find(checks.begin(), checks.end(), "Newton"), checks.end()) << join(checks);
    EXPECT_NE(std::find(checks.begin(), checks.end(), "total energy"), checks.end()) << join(checks);
    // The explicit run records no implicit part: null, not zeros.
    const std::string plain = tmp.file("explicit");
    ASSERT_EQ(
        run_suite({"mpm", "--mesh=box:6,6,6", "--steps=2", "--vtk-every=0", "--no-png", "--out=" + plain}, 60).status,
        0);
    EXPECT_TRUE(read_json(plain + "/mpm.json")["implicit"].is_null());
    // One Newton iteration cannot reach a nonlinear step's tolerance: status 3, said in one line
    // after the progress, the files written and marked unverified.
    const std::string failed = tmp.file("failed");
    const Outcome f = run_suite({"mpm", "--integrator=implicit", "--dt=0.2", "--newton-max=1", "--mesh=box:6,6,6",
                                 "--steps=5", "--vtk-every=0", "--no-png", "--out=" + failed},
                                60);
    ASSERT_EQ(f.status, 3) << describe(f);
    EXPECT_NE(
        f.err.find("suite: error: mpm check failed: Newton: step 1 (t = 0 s): Newton did not converge in 1 iterations"),
        std::string::npos)
        << f.err;
    const nlohmann::json fd = read_json(failed + "/mpm.json");
    EXPECT_EQ(fd["verification"]["passed"], false);
    EXPECT_EQ(fd["complete"], false);
    EXPECT_EQ(fd["steps"], 0);
}

TEST(MpmCli, DryRunChecksEverythingAndWritesNothing) {
    TempDir tmp;
    const std::string dir = tmp.file("dam");
    const Outcome r =
        run_suite({"mpm", "--mesh=box:8,8,8", "--steps=100", "--vtk-every=30", "--dry-run", "--out=" + dir}, 60);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("elements"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("5 snapshot(s)"), std::string::npos) << r.out;  // 0, 30, 60, 90 and the last, 100
    EXPECT_TRUE(r.err.empty()) << r.err;
    EXPECT_TRUE(tmp.entries().empty()) << join(tmp.entries());
    // A dry run still refuses what the run would refuse, the library's checks included.
    const Outcome bad =
        run_suite({"mpm", "--mesh=box:8,8,8", "--poisson=0.49999999", "--dt=0.01", "--dry-run", "--out=" + dir}, 60);
    EXPECT_EQ(bad.status, 2) << describe(bad);
    EXPECT_TRUE(tmp.entries().empty()) << join(tmp.entries());
    const Outcome no_out = run_suite({"mpm", "--mesh=box:6,6,6", "--dry-run"}, 60);
    EXPECT_EQ(no_out.status, 0) << describe(no_out);
    EXPECT_NE(no_out.out.find("nothing would be written"), std::string::npos) << no_out.out;
}

TEST(MpmCli, TheExamplesOfHelpAreAcceptedAsWritten) {
    const Outcome help = run_suite({"mpm", "--help"}, 60);
    ASSERT_EQ(help.status, 0) << describe(help);
    std::istringstream in(help.out);
    int examples = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("  ./suite mpm ", 0) != 0) continue;
        std::vector<std::string> args;
        std::istringstream words(line.substr(line.find("mpm")));
        for (std::string w; words >> w && w[0] != '#';) args.push_back(w);
        args.push_back("--dry-run");
        const Outcome r = run_suite(args, 60);
        EXPECT_EQ(r.status, 0) << line << "\n" << describe(r);
        ++examples;
    }
    EXPECT_GE(examples, 4) << help.out;
}

TEST(MpmCli, ARunForcedPastTheStableStepExitsOneNamingWhatBlewUp) {
    // Forced to 3 and 10 times the stable step the elastic waves grow within a few steps, and
    // the walls' clamping keeps every value finite (1e24 J by step 400 at 3 times): the energy
    // bound tells. (At 1.5 times a NaN came at step 196 and the bound at step 170; how slowly
    // a marginal step grows is the library's physics, so the test stays well past it.)
    TempDir tmp;
    for (const std::string courant : {"3", "10"}) {
        const std::string dir = tmp.file("blow" + courant);
        const Outcome r = run_suite({"mpm", "--mesh=box:6,6,6", "--steps=3000", "--vtk-every=0", "--force",
                                     "--courant=" + courant, "--no-png", "--out=" + dir},
                                    120);
        ASSERT_EQ(r.status, 1) << courant << "\n" << describe(r);
        // The error is the last line on stderr, after the progress lines.
        const std::size_t last = r.err.rfind('\n', r.err.size() - 2);
        EXPECT_EQ(r.err.substr(last == std::string::npos ? 0 : last + 1).rfind("suite: error: mpm check failed: ", 0),
                  0u)
            << r.err;
        EXPECT_NE(r.err.find("energy bound: after step"), std::string::npos) << r.err;
        const nlohmann::json doc = read_json(dir + "/mpm.json");
        EXPECT_EQ(doc["complete"], false);
        EXPECT_EQ(doc["verification"]["passed"], false);
        EXPECT_TRUE(doc["mass"]["final"].is_null()) << "not measured is not zero";
        EXPECT_LT(doc["steps"].get<int>(), 3000);
        EXPECT_EQ(count_lines(slurp(dir + "/front.csv")), 1u + 1u + doc["steps"].get<std::size_t>());
    }
}

TEST(MpmCli, AnInterruptedRunKeepsItsFilesAndExits128PlusTheSignal) {
    TempDir tmp;
    const std::string dir = tmp.file("long");
    int out_fd = -1, err_fd = -1;
    const pid_t pid = spawn(
        {SUITE_BINARY, "mpm", "--mesh=box:6,6,6", "--steps=100000000", "--vtk-every=1000", "--no-png", "--out=" + dir},
        out_fd, err_fd);
    // Stopped once it has printed a progress line (a tenth of 10^8 steps is hours: none comes)
    // or, more to the point, once its first snapshot is there: it is stepping.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!fs::exists(dir + "/particles_001000.vtu") && std::chrono::steady_clock::now() < deadline) usleep(20000);
    kill(pid, SIGTERM);
    const Outcome r = finish(pid, out_fd, err_fd, 60);
    ASSERT_EQ(r.status, 128 + SIGTERM) << describe(r);
    EXPECT_NE(r.err.find("interrupted by signal 15"), std::string::npos) << r.err;
    const nlohmann::json doc = read_json(dir + "/mpm.json");
    EXPECT_EQ(doc["complete"], false);
    EXPECT_EQ(doc["interrupted_by_signal"], SIGTERM);
    EXPECT_EQ(doc["verification"]["passed"], true) << doc.dump(1);
    EXPECT_TRUE(fs::exists(dir + "/particles.pvd"));
    EXPECT_EQ(doc["snapshots"].back()["step"], doc["steps"]) << "the last state is kept";
}

TEST(MpmCli, TheDamBreakFlowsAndRecordsHowTheParticlesOrderDecays) {
    TempDir tmp;
    const std::string dir = tmp.file("water");
    const Outcome r = run_suite(
        {"mpm", "--case=dam-break", "--mesh=box:6,6,6", "--steps=300", "--vtk-every=0", "--no-png", "--out=" + dir},
        120);
    ASSERT_EQ(r.status, 0) << describe(r);
    const nlohmann::json doc = nlohmann::json::parse(slurp(dir + "/mpm.json"));
    EXPECT_EQ(doc["settings"]["case"], "dam-break");
    EXPECT_EQ(doc["settings"]["material"], "fluid");
    EXPECT_TRUE(doc["settings"]["young"].is_null()) << "a fluid has no Young's modulus";
    EXPECT_EQ(doc["settings"]["particles"], "seeded");
    EXPECT_GT(doc["front"]["final"].get<double>(), 0.9) << "the water reached the far wall";
    EXPECT_LT(doc["dt_range"]["min"].get<double>(), doc["dt_range"]["max"].get<double>());
    EXPECT_GT(doc["locality"]["final"]["mean_curve_gap"].get<double>(),
              5 * doc["locality"]["initial"]["mean_curve_gap"].get<double>());
    std::vector<std::string> names;
    for (const auto& c : doc["verification"]["checks"]) names.push_back(c["check"]);
    EXPECT_EQ(names, (std::vector<std::string>{"finite and inside the box", "energy bound", "total energy",
                                               "Ritter front", "mass", "nodal mass"}));
    EXPECT_NE(r.out.find("suite mpm: dam-break on box:6,6,6"), std::string::npos) << r.out;
}

TEST(MpmCli, TheKernelsTakeTheCaseAndAWarmUpThatReachesTheMixedFlow) {
    TempDir tmp;
    const std::string out = tmp.file("r.json");
    const Outcome r =
        run_suite({"--kernel=mpm-step", "--case=dam-break", "--warm-steps=60", "--mesh=box:6,6,6",
                   "--particles=seeded,sorted", "--sort-every=5", "--threads=1", "--reps=2", "--quiet", "--out=" + out},
                  120);
    ASSERT_EQ(r.status, 0) << describe(r);
    const nlohmann::json doc = read_json(out);
    ASSERT_EQ(doc["results"].size(), 2u);
    for (const auto& rec : doc["results"]) {
        EXPECT_EQ(rec["parameters"]["case"], "dam-break") << "a named parameter is recorded by its name";
        EXPECT_EQ(rec["parameters"]["warm-steps"], 60);
        const std::string detail = rec["verification"]["detail"];
        EXPECT_EQ(detail.rfind("dam-break on box grid box:6,6,6", 0), 0u) << detail;
        EXPECT_NE(detail.find("after 60 untimed steps"), std::string::npos) << detail;
        EXPECT_TRUE(rec["verification"]["passed"].get<bool>()) << detail;
        // The water moved during the warm-up: 60 steps plus the timed ones, past 0.1 s.
        EXPECT_GT(rec["facts"]["simulated"]["value"].get<double>(), 0.1);
    }
}
