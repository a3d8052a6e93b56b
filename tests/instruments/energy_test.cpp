// RAPL energy without RAPL: captured sysfs trees (tests/fixtures/sysfs) copied to a scratch
// folder, their counters moved between readings, and the joules checked exactly.
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "harness/common/units.hpp"
#include "rapl/energy.hpp"
#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite;

namespace {

const std::string kFixtures = std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/sysfs/";

// A writable copy of a fixture tree.
struct Tree {
    test::TempDir dir;
    std::string root;
    explicit Tree(const std::string& name) : root(dir.file(name)) {
        fs::copy(kFixtures + name, root, fs::copy_options::recursive);
    }
    std::string zone(const std::string& z) const { return root + "/class/powercap/" + z + "/energy_uj"; }
    // Replaces the file in one step (a reader never sees half a number).
    void set(const std::string& z, std::uint64_t uj) const {
        const std::string tmp = zone(z) + ".new";
        std::ofstream(tmp) << uj << "\n";
        fs::rename(tmp, zone(z));
    }
};

const EnergySource* find(const std::vector<EnergySource>& v, const std::string& domain, std::optional<int> socket) {
    for (const auto& s : v)
        if (s.domain == domain && s.socket == socket) return &s;
    return nullptr;
}

const DomainEnergy* find(const EnergyReadings& r, const std::string& domain, std::optional<int> socket) {
    for (const auto& d : r.domains)
        if (d.domain == domain && d.socket == socket) return &d;
    return nullptr;
}

}  // namespace

TEST(EnergyBackendOption, AcceptsTheFourNamesAndRefusesOthers) {
    EXPECT_EQ(parse_energy_backend("auto"), EnergyBackend::automatic);
    EXPECT_EQ(parse_energy_backend("sysfs"), EnergyBackend::sysfs);
    EXPECT_EQ(parse_energy_backend("perf"), EnergyBackend::perf);
    EXPECT_EQ(parse_energy_backend("none"), EnergyBackend::none);
    try {
        parse_energy_backend("rapl");
        FAIL() << "accepted --energy=rapl";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("accepted: auto, sysfs, perf, none"), std::string::npos) << e.what();
    }
}

TEST(Powercap, TwoSocketIntelHasPackageAndDramPerSocketAndTheMmioCopyIsSkipped) {
    std::string reason;
    const auto sources = discover_powercap(kFixtures + "intel-2socket", reason);
    ASSERT_EQ(sources.size(), 4u) << reason;
    for (int s : {0, 1}) {
        const EnergySource* pkg = find(sources, "package", s);
        const EnergySource* dram = find(sources, "dram", s);
        ASSERT_NE(pkg, nullptr) << "socket " << s;
        ASSERT_NE(dram, nullptr) << "socket " << s;
        EXPECT_EQ(pkg->max_raw, 262143328850u);
        EXPECT_EQ(dram->max_raw, 65712999613u);
        EXPECT_TRUE(pkg->reason.empty()) << pkg->reason;
        EXPECT_NE(pkg->where.find("intel-rapl:" + std::to_string(s) + "/energy_uj"), std::string::npos) << pkg->where;
    }
}

TEST(Powercap, AmdEpycHasPackageAndCore) {
    std::string reason;
    const auto sources = discover_powercap(kFixtures + "amd-epyc", reason);
    ASSERT_EQ(sources.size(), 2u) << reason;
    EXPECT_NE(find(sources, "package", 0), nullptr);
    EXPECT_NE(find(sources, "core", 0), nullptr);
}

TEST(Powercap, PsysBelongsToNoSocket) {
    std::string reason;
    const auto sources = discover_powercap(kFixtures + "wrap", reason);
    ASSERT_EQ(sources.size(), 2u);
    EXPECT_NE(find(sources, "psys", std::nullopt), nullptr);
}

TEST(Powercap, MissingTreeSaysSo) {
    std::string reason;
    EXPECT_TRUE(discover_powercap(kFixtures + "missing", reason).empty());
    EXPECT_NE(reason.find("class/powercap does not exist"), std::string::npos) << reason;
    const EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, kFixtures + "missing");
    EXPECT_TRUE(m.requested());
    EXPECT_FALSE(m.available());
    EXPECT_NE(m.reason().find("does not exist"), std::string::npos) << m.reason();
}

TEST(Powercap, JoulesAcrossAWrapAroundAreExact) {
    EnergySource s;
    s.max_raw = 262143328850;  // µJ
    s.joules_per_unit = 1e-6;
    EXPECT_DOUBLE_EQ(joules_between(s, 1000000, 3500000), 2.5);
    // 1000 µJ up to the maximum, then 5000 µJ after the wrap to 0.
    EXPECT_DOUBLE_EQ(joules_between(s, 262143327850u, 5000), 0.006);
}

TEST(EnergyMeterTest, ExactJoulesWattsAndPerByteFromMovedCounters) {
    Tree t("intel-2socket");
    EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    ASSERT_TRUE(m.available()) << m.reason();
    EXPECT_EQ(m.backend(), "sysfs");
    // Two repetitions of 4 calls each: package-0 uses 2 J then 3 J, dram-0 0.5 J twice.
    std::uint64_t pkg = 100000000, dram = 5000000;
    for (double joules : {2.0, 3.0}) {
        m.start();
        pkg += static_cast<std::uint64_t>(joules * 1e6);
        dram += 500000;
        t.set("intel-rapl:0", pkg);
        t.set("intel-rapl:0:0", dram);
        m.stop(0.5);
    }
    const EnergyReadings r = m.take(4, 1000.0, 24000.0, 0.125);
    ASSERT_TRUE(r.available) << r.reason;
    const DomainEnergy* p0 = find(r, "package", 0);
    ASSERT_NE(p0, nullptr);
    ASSERT_TRUE(p0->available) << p0->reason;
    EXPECT_DOUBLE_EQ(p0->joules_total, 5.0);
    EXPECT_DOUBLE_EQ(p0->joules_per_call.min, 0.5);
    EXPECT_DOUBLE_EQ(p0->joules_per_call.max, 0.75);
    EXPECT_DOUBLE_EQ(p0->joules_per_call.median, 0.625);
    EXPECT_DOUBLE_EQ(*p0->watts_median, 5.0);  // (4 W + 6 W) / 2
    EXPECT_DOUBLE_EQ(*p0->nj_per_byte, 0.625 / 24000.0 * 1e9);
    EXPECT_DOUBLE_EQ(*p0->nj_per_element, 0.625 / 1000.0 * 1e9);
    EXPECT_FALSE(p0->idle_watts.has_value());
    const DomainEnergy* d0 = find(r, "dram", 0);
    ASSERT_TRUE(d0 && d0->available);
    EXPECT_DOUBLE_EQ(d0->joules_total, 1.0);
    // Socket 1 did not move: unavailable with the reason, not 0 J.
    const DomainEnergy* p1 = find(r, "package", 1);
    ASSERT_NE(p1, nullptr);
    EXPECT_FALSE(p1->available);
    EXPECT_NE(p1->reason.find("did not advance"), std::string::npos) << p1->reason;
    EXPECT_DOUBLE_EQ(p1->joules_total, 0.0);  // never reported: its JSON carries joules_per_call null
}

TEST(EnergyMeterTest, AFrozenCounterSaysWhatItRead) {
    Tree t("intel-2socket");
    t.set("intel-rapl:1", 262143328850);  // max_energy_range_uj: stuck at the top, not counting
    t.set("intel-rapl:1:0", 0);
    EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    ASSERT_TRUE(m.available()) << m.reason();
    for (std::uint64_t uj : {2000000u, 3000000u}) {
        m.start();
        t.set("intel-rapl:0", uj);
        m.stop(0.1);
    }
    const EnergyReadings r = m.take(1, 1.0, 1.0, 0.1);
    const DomainEnergy* p1 = find(r, "package", 1);
    ASSERT_NE(p1, nullptr);
    EXPECT_FALSE(p1->available);
    EXPECT_NE(p1->reason.find("did not advance over 2 repetitions"), std::string::npos) << p1->reason;
    EXPECT_NE(p1->reason.find(t.zone("intel-rapl:1") +
                              " read 262143328850 µJ every time, the counter's maximum (max_energy_range_uj)"),
              std::string::npos)
        << p1->reason;
    EXPECT_EQ(p1->reason.find("reads 0"), std::string::npos) << p1->reason;
    const DomainEnergy* d1 = find(r, "dram", 1);
    ASSERT_NE(d1, nullptr);
    EXPECT_NE(d1->reason.find("read 0 µJ every time"), std::string::npos) << d1->reason;
}

TEST(Powercap, AFifoIsNotReadAndThatDomainSaysWhy) {
    Tree t("amd-epyc");
    fs::remove(t.zone("intel-rapl:0"));
    ASSERT_EQ(mkfifo(t.zone("intel-rapl:0").c_str(), 0644), 0);  // no writer: a plain open() would wait forever
    std::string reason;
    const auto sources = discover_powercap(t.root, reason);
    ASSERT_EQ(sources.size(), 2u) << reason;
    const EnergySource* pkg = find(sources, "package", 0);
    ASSERT_NE(pkg, nullptr);
    EXPECT_NE(pkg->reason.find("is a named pipe (FIFO), which a sysfs attribute never is"), std::string::npos)
        << pkg->reason;
    EXPECT_TRUE(find(sources, "core", 0)->reason.empty());
    // The same for the zone's name: that zone is listed, unavailable, with the reason.
    fs::remove(t.root + "/class/powercap/intel-rapl:0:0/name");
    ASSERT_EQ(mkfifo((t.root + "/class/powercap/intel-rapl:0:0/name").c_str(), 0644), 0);
    const auto again = discover_powercap(t.root, reason);
    ASSERT_EQ(again.size(), 2u);
    EXPECT_NE(again[1].reason.find("name is a named pipe (FIFO)"), std::string::npos) << again[1].reason;
    const EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    EXPECT_FALSE(m.available());
    EXPECT_NE(m.reason().find("FIFO"), std::string::npos) << m.reason();
}

TEST(Powercap, ZoneAndSocketNumbersBeyondAnIntAreUnavailableWithTheReason) {
    Tree t("amd-epyc");
    const std::string base = t.root + "/class/powercap/";
    fs::rename(base + "intel-rapl:0:0", base + "intel-rapl:0:99999999999");
    std::ofstream(base + "intel-rapl:0/name") << "package-99999999999\n";
    std::string reason;
    const auto sources = discover_powercap(t.root, reason);  // std::stoi threw here: "suite: error: stoi"
    ASSERT_EQ(sources.size(), 2u) << reason;
    EXPECT_EQ(sources[0].domain, "package");
    EXPECT_FALSE(sources[0].socket.has_value());
    EXPECT_NE(sources[0].reason.find("'package-99999999999' gives a socket number above 2147483647"), std::string::npos)
        << sources[0].reason;
    EXPECT_NE(sources[1].reason.find("powercap zone intel-rapl:0:99999999999 has a number above 2147483647"),
              std::string::npos)
        << sources[1].reason;
    const EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    EXPECT_FALSE(m.available());
    EXPECT_NE(m.reason().find("99999999999"), std::string::npos) << m.reason();
    // A zone number beyond 64 bits too (sorted last, refused the same way).
    fs::rename(base + "intel-rapl:0:99999999999", base + "intel-rapl:0:99999999999999999999999");
    EXPECT_NE(discover_powercap(t.root, reason)[1].reason.find("has a number above"), std::string::npos);
}

TEST(EnergyMeterTest, AWrapAroundDuringARepetition) {
    Tree t("wrap");
    EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    ASSERT_TRUE(m.available()) << m.reason();
    m.start();
    t.set("intel-rapl:0", 5000);  // wrapped: 1000 µJ to the maximum, then 5000 µJ
    t.set("intel-rapl:1", 123 + 7000);
    m.stop(0.001);
    const EnergyReadings r = m.take(1, 1.0, 1.0, 0.001);
    const DomainEnergy* p = find(r, "package", 0);
    ASSERT_TRUE(p && p->available);
    EXPECT_DOUBLE_EQ(p->joules_total, 0.006);
    const DomainEnergy* psys = find(r, "psys", std::nullopt);
    ASSERT_TRUE(psys && psys->available);
    EXPECT_DOUBLE_EQ(psys->joules_total, 0.007);
}

TEST(EnergyMeterTest, ACounterThatVanishesMidRunIsLostForThatPointOnly) {
    Tree t("amd-epyc");
    EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    ASSERT_TRUE(m.available());
    m.start();
    fs::remove(t.zone("intel-rapl:0"));
    t.set("intel-rapl:0:0", 2000000);
    m.stop(0.1);
    EnergyReadings r = m.take(1, 1.0, 1.0, 0.1);
    const DomainEnergy* pkg = find(r, "package", 0);
    ASSERT_NE(pkg, nullptr);
    EXPECT_FALSE(pkg->available);
    EXPECT_NE(pkg->reason.find("during the run"), std::string::npos) << pkg->reason;
    EXPECT_TRUE(find(r, "core", 0)->available);
    // The file is back for the next point, and so is the measurement.
    t.set("intel-rapl:0", 4000000);
    m.start();
    t.set("intel-rapl:0", 4100000);
    t.set("intel-rapl:0:0", 2050000);
    m.stop(0.1);
    r = m.take(1, 1.0, 1.0, 0.1);
    ASSERT_TRUE(find(r, "package", 0)->available) << find(r, "package", 0)->reason;
    EXPECT_DOUBLE_EQ(find(r, "package", 0)->joules_total, 0.1);
}

TEST(EnergyMeterTest, IdleBaselineIsSubtracted) {
    Tree t("amd-epyc");
    EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
    ASSERT_TRUE(m.available());
    // While the meter sleeps 0.3 s, the package counter moves 3 J: 10 W idle if the sleep took
    // exactly 0.3 s, less if it overslept on a loaded machine.
    std::thread mover([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        t.set("intel-rapl:0", 4000000 + 3000000);
        t.set("intel-rapl:0:0", 1000000 + 200000);
    });
    m.measure_idle(0.3);
    mover.join();
    m.start();
    t.set("intel-rapl:0", 7000000 + 3000000);
    t.set("intel-rapl:0:0", 1200000 + 100000);
    m.stop(0.1);
    const EnergyReadings r = m.take(1, 1.0, 1.0, 0.1);
    const DomainEnergy* p = find(r, "package", 0);
    ASSERT_TRUE(p && p->available);
    ASSERT_TRUE(p->idle_watts.has_value());
    EXPECT_LE(*p->idle_watts, 10.0 + 1e-9);  // 3 J over the measured sleep: 0.3 s or more
    EXPECT_GT(*p->idle_watts, 3.0);          // ... but not a whole second more
    EXPECT_DOUBLE_EQ(*p->joules_above_idle_per_call, 3.0 - *p->idle_watts * 0.1);
}

TEST(EnergyMeterTest, PermissionDeniedIsUnavailableWithTheReason) {
    Tree t("intel-2socket");
    fs::permissions(t.dir.path(), fs::perms::others_read | fs::perms::others_exec,
                    fs::perm_options::add);  // mkdtemp made it 0700
    for (const char* z : {"intel-rapl:0", "intel-rapl:0:0", "intel-rapl:1", "intel-rapl:1:0"})
        fs::permissions(t.zone(z), fs::perms::owner_read);
    // Root reads any file; the check runs as an unprivileged user, like a user since Linux 5.10.
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0)) _exit(3);
        std::string reason;
        const auto sources = discover_powercap(t.root, reason);
        if (sources.size() != 4) _exit(4);
        for (const auto& s : sources)
            if (s.reason.find("readable only by root") == std::string::npos) _exit(5);
        const EnergyMeter m = EnergyMeter::open(EnergyBackend::sysfs, t.root);
        if (m.available() || m.reason().find("readable only by root") == std::string::npos) _exit(6);
        _exit(0);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    ASSERT_TRUE(WIFEXITED(st));
    if (WEXITSTATUS(st) == 3) GTEST_SKIP() << "cannot drop to uid 65534 here to model an unprivileged user";
    EXPECT_EQ(WEXITSTATUS(st), 0)
        << "1: not 4 sources, 5: a source without the root-only reason, 6: the meter did not say why";
}

TEST(PerfPower, EventsScaleAndSocketsAreReadFromTheTree) {
    std::string reason;
    const auto sources = discover_perf_power(kFixtures + "perf-power", reason);
    ASSERT_EQ(sources.size(), 4u) << reason;
    for (int s : {0, 1})
        for (const char* d : {"package", "dram"}) {
            const EnergySource* e = find(sources, d, s);
            ASSERT_NE(e, nullptr) << d << " socket " << s;
            EXPECT_DOUBLE_EQ(e->joules_per_unit, 2.3283064365386962890625e-10);
            EXPECT_EQ(e->max_raw, 0u);
            // PMU type 4242 does not exist on this machine: opening fails, with the reason.
            EXPECT_EQ(e->fd, -1);
            EXPECT_NE(e->reason.find("cannot open perf power/energy-"), std::string::npos) << e->reason;
        }
    EXPECT_NE(find(sources, "package", 1)->where.find("CPU 28"), std::string::npos);
    const EnergyMeter m = EnergyMeter::open(EnergyBackend::perf, kFixtures + "perf-power");
    EXPECT_FALSE(m.available());
    EXPECT_NE(m.reason().find("cannot open"), std::string::npos) << m.reason();
}

TEST(PerfPower, AbsentPmuAndAutoFallbackReasonsNameBothBackends) {
    const EnergyMeter m = EnergyMeter::open(EnergyBackend::automatic, kFixtures + "missing");
    EXPECT_FALSE(m.available());
    EXPECT_NE(m.reason().find("powercap sysfs:"), std::string::npos) << m.reason();
    EXPECT_NE(m.reason().find("perf power PMU: no perf power PMU"), std::string::npos) << m.reason();
}

TEST(PerfPower, AutoPrefersSysfsWhereItCanBeRead) {
    const EnergyMeter m = EnergyMeter::open(EnergyBackend::automatic, kFixtures + "amd-epyc");
    EXPECT_TRUE(m.available()) << m.reason();
    EXPECT_EQ(m.backend(), "sysfs");
}
