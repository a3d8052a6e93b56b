#include "harness/results/history.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <tuple>

#include "harness/results/context_fields.hpp"

namespace suite {

using nlohmann::json;

namespace {

// FNV-1a, 64 bits: stable across builds and machines (std::hash is neither).
struct Fnv1a {
    std::uint64_t h = 1469598103934665603ULL;
    void add(const std::string& s) {
        for (unsigned char c : s) {
            h ^= c;
            h *= 1099511628211ULL;
        }
        h ^= 0x1f;  // a separator, so that "ab","c" and "a","bc" differ
        h *= 1099511628211ULL;
    }
    std::string hex() const {
        char buf[17];
        std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
        return buf;
    }
};

std::string exact_text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

std::string history_added_at() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

const char* direction_text(Direction d) { return d == Direction::higher_is_better ? "higher" : "lower"; }

// The columns of a series, in the order the queries below select them. The rank scope is one:
// an MPI run's ranks and its aggregate are never one series. A file of schema version 1 or 2,
// read as it is, has no such column (migration 3 added it): every record in it is of a run of
// one process (""). A rank's host (rank_host) is stored but is no part of the identity: the gate
// looks a series up by its point (PointKey), which has none.
std::string history_series_columns(int version) {
    return std::string(
               "r.fingerprint, r.machine, r.context_class, c.hugepages, c.kernel, c.variant, c.access, c.size_kind, "
               "c.size, c.threads, "
               "c.pin, c.placement, c.params, c.figure, c.unit, c.direction, ") +
           (version >= 3 ? "c.rank_scope" : "''");
}
constexpr int history_series_column_count = 17;

}  // namespace

std::string machine_fingerprint(const json& c) {
    // The raw JSON of each field, not its display text, so that a change in how a field is shown
    // never splits a machine's history in two.
    Fnv1a fp;
    for (const char* field : {"host", "cpu_model", "sockets", "numa_node_count", "cores", "pus", "memory_bytes"})
        fp.add(c.is_object() && c.contains(field) ? c[field].dump() : "null");
    return fp.hex();
}

RunIdentity identify_run(const ResultFile& file, const std::string& commit, const std::string& branch) {
    const json& c = file.context;
    RunIdentity id;
    id.fingerprint = machine_fingerprint(c);
    id.machine =
        context_text(c, "host") + " (" + context_text(c, "cpu_model") + ", " + context_text(c, "cores") + " cores)";
    id.context_class = context_text(c, "compiler") + ", " + context_text(c, "compiler_flags") + ", " +
                       context_text(c, "build_type") + ", " + context_text(c, "instruction_set") + ", THP " +
                       context_text(c, "transparent_hugepages");
    const std::string revision = context_text(c, "git_revision");
    id.commit = !commit.empty() ? commit : revision != "?" && !revision.empty() ? revision : "unknown";
    id.branch = branch.empty() ? "unknown" : branch;
    id.date = context_text(c, "date");
    return id;
}

std::string series_class(const std::string& run_class, const std::string& hugepages) {
    return hugepages.empty() ? run_class : run_class + ", huge pages " + hugepages;
}

std::string run_content_hash(const ResultFile& file) {
    Fnv1a h;
    h.add(file.context.dump());
    for (const auto& p : file.points) {
        h.add(p.key.label());
        h.add(p.key.size_kind + " " + p.hugepages + (p.verified ? " verified" : " failed") +
              (p.unstable ? " unstable " + p.unstable_why : ""));
        for (const auto& m : p.measures) {
            h.add(m.name + " " + m.unit + " " + exact_text(m.best) + " " + exact_text(m.median) + " " +
                  exact_text(m.noise));
            for (double s : m.samples) h.add(exact_text(s));
        }
    }
    return h.hex();
}

std::vector<AddOutcome> History::add(const std::vector<ResultFile>& files, const std::string& commit,
                                     const std::string& branch) {
    std::vector<AddOutcome> out;
    SqlTransaction t(db_);
    // Under the write lock: a newer suite may have migrated the file since it was opened.
    if (const int v = history_file_version(db_); v > history_schema_version)
        throw InputError(path() + ": schema version " + std::to_string(v) + " is newer than this suite's (" +
                         std::to_string(history_schema_version) + "); nothing was changed");
    SqlStatement find = db_.prepare("SELECT id, commit_sha FROM runs WHERE content_hash = ?1");
    SqlStatement run = db_.prepare(
        "INSERT INTO runs (content_hash, fingerprint, machine, context_class, commit_sha, branch, date, source, added, "
        "context) "
        "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
    SqlStatement record = db_.prepare(
        "INSERT INTO records (run_id, kernel, variant, access, size_kind, size, threads, pin, placement, params, "
        "hugepages, figure, unit, "
        "direction, median, noise, count_per_call, samples, verified, unstable, unstable_why, rank_scope, rank_host) "
        "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19, ?20, ?21, ?22, "
        "?23)");
    const std::string now = history_added_at();
    for (const auto& f : files) {
        AddOutcome o;
        o.source = f.path;
        o.id = identify_run(f, commit, branch);
        const std::string hash = run_content_hash(f);
        find.reset();
        find.bind(1, hash);
        if (find.step()) {
            o.run_id = find.integer(0);
            o.stored_commit = find.text(1);
            out.push_back(o);
            continue;
        }
        run.reset();
        run.bind(1, hash)
            .bind(2, o.id.fingerprint)
            .bind(3, o.id.machine)
            .bind(4, o.id.context_class)
            .bind(5, o.id.commit)
            .bind(6, o.id.branch);
        run.bind(7, o.id.date).bind(8, f.path).bind(9, now).bind(10, f.context.dump());
        run.run();
        o.run_id = db_.last_insert_id();
        o.added = true;
        o.stored_commit = o.id.commit;
        for (const auto& p : f.points) {
            const PointKey& k = p.key;
            for (const auto& m : p.measures) {
                record.reset();
                record.bind(1, o.run_id).bind(2, k.kernel).bind(3, k.variant).bind(4, k.access).bind(5, k.size_kind);
                record.bind(6, static_cast<std::int64_t>(k.size))
                    .bind(7, static_cast<std::int64_t>(k.threads))
                    .bind(8, k.pin)
                    .bind(9, k.placement);
                record.bind(10, params_json(k.params).dump()).bind(11, p.hugepages).bind(12, m.name).bind(13, m.unit);
                record.bind(14, std::string(direction_text(m.direction)))
                    .bind(15, m.median)
                    .bind(16, m.noise)
                    .bind(17, m.count_per_call);
                record.bind(18, json(m.samples).dump())
                    .bind(19, std::int64_t{p.verified})
                    .bind(20, std::int64_t{p.unstable});
                record.bind(21, p.unstable_why).bind(22, k.rank_scope);
                record.bind(23, p.mpi.scope == RankOrigin::Scope::rank ? p.mpi.host : std::string());
                record.run();
                ++o.figures;
            }
        }
        out.push_back(o);
    }
    t.commit();
    return out;
}

std::int64_t History::find_run(const std::string& content_hash) const {
    SqlStatement s = db_.prepare("SELECT id FROM runs WHERE content_hash = ?1");
    s.bind(1, content_hash);
    return s.step() ? s.integer(0) : 0;
}

std::vector<std::pair<std::string, std::string>> History::machines_matching(const std::string& text) const {
    std::vector<std::pair<std::string, std::string>> out;
    SqlStatement s = db_.prepare("SELECT fingerprint, max(machine) FROM runs GROUP BY fingerprint ORDER BY 2, 1");
    while (s.step()) {
        const std::string fp = s.text(0), label = s.text(1);
        if (text.empty() || fp.rfind(text, 0) == 0 || label.find(text) != std::string::npos)
            out.emplace_back(fp, label);
    }
    return out;
}

std::vector<Series> History::series(const SeriesFilter& filter) const {
    const std::string series_columns = history_series_columns(version_);
    SqlStatement s = db_.prepare(
        "SELECT " + series_columns +
        ", r.commit_sha, r.branch, r.date, r.id, c.median, c.noise, c.samples, c.unstable, c.count_per_call "
        "FROM records c JOIN runs r ON r.id = c.run_id "
        "WHERE c.verified = 1 AND (?1 = '' OR c.kernel = ?1) AND (?2 = '' OR r.context_class = ?2) ORDER BY " +
        series_columns + ", r.date, r.id");
    s.bind(1, filter.kernel).bind(2, filter.context_class);
    std::vector<Series> out;
    std::vector<std::string> last;  // the series columns of the previous row
    while (s.step()) {
        std::vector<std::string> cols;
        for (int i = 0; i < history_series_column_count; ++i) cols.push_back(s.text(i));
        if (!filter.fingerprints.empty() &&
            std::find(filter.fingerprints.begin(), filter.fingerprints.end(), cols[0]) == filter.fingerprints.end())
            continue;
        if (out.empty() || cols != last) {
            Series x;
            x.fingerprint = cols[0];
            x.machine = cols[1];
            x.context_class = series_class(cols[2], cols[3]);
            PointKey& k = x.key;
            k.kernel = cols[4];
            k.variant = cols[5];
            k.access = cols[6];
            k.size_kind = cols[7];
            k.size = static_cast<std::uint64_t>(s.integer(8));
            k.threads = static_cast<int>(s.integer(9));
            k.pin = cols[10];
            k.placement = cols[11];
            k.params = params_from_json(json::parse(cols[12]), k.kernel);
            k.rank_scope = cols[16];
            x.figure = cols[13];
            x.unit = cols[14];
            x.direction = cols[15] == "higher" ? Direction::higher_is_better : Direction::lower_is_better;
            out.push_back(std::move(x));
            last = std::move(cols);
        }
        SeriesEntry e;
        e.commit = s.text(17);
        e.branch = s.text(18);
        e.date = s.text(19);
        e.run_id = s.integer(20);
        e.median = s.real(21);
        e.noise = s.real(22);
        e.samples = json::parse(s.text(23)).get<std::vector<double>>();
        e.unstable = s.integer(24) != 0;
        e.count_per_call = s.real(25);
        out.back().entries.push_back(std::move(e));
    }
    const auto identity = [](const Series& x) {
        return std::tie(x.machine, x.fingerprint, x.context_class, x.key, x.figure, x.unit);
    };
    std::stable_sort(out.begin(), out.end(),
                     [&](const Series& a, const Series& b) { return identity(a) < identity(b); });
    // A build before result schema 2 stored a named parameter as its index, which params_from_json
    // reads as the name: such rows join the series of the same point stored by name.
    std::vector<Series> merged;
    for (auto& x : out) {
        if (merged.empty() || identity(merged.back()) != identity(x)) {
            merged.push_back(std::move(x));
            continue;
        }
        auto& e = merged.back().entries;
        e.insert(e.end(), x.entries.begin(), x.entries.end());
        std::stable_sort(e.begin(), e.end(), [](const SeriesEntry& a, const SeriesEntry& b) {
            return std::tie(a.date, a.run_id) < std::tie(b.date, b.run_id);
        });
    }
    return merged;
}

std::size_t History::run_count() const {
    SqlStatement s = db_.prepare("SELECT count(*) FROM runs");
    s.step();
    return static_cast<std::size_t>(s.integer(0));
}

std::vector<MachineSummary> History::summary() const {
    std::vector<MachineSummary> out;
    SqlStatement machines = db_.prepare(
        "SELECT fingerprint, max(machine), count(*), count(DISTINCT context_class) FROM runs GROUP BY fingerprint "
        "ORDER BY 2, 1");
    SqlStatement series =
        db_.prepare("SELECT count(*) FROM (SELECT DISTINCT " + history_series_columns(version_) +
                    " FROM records c JOIN runs r ON r.id = c.run_id WHERE c.verified = 1 AND r.fingerprint = ?1)");
    SqlStatement commits = db_.prepare(
        "SELECT commit_sha, branch, max(date), count(*) FROM runs WHERE fingerprint = ?1 GROUP BY commit_sha, branch "
        "ORDER BY min(date), commit_sha");
    while (machines.step()) {
        MachineSummary m;
        m.fingerprint = machines.text(0);
        m.machine = machines.text(1);
        m.runs = static_cast<std::size_t>(machines.integer(2));
        m.context_classes = static_cast<std::size_t>(machines.integer(3));
        series.reset();
        series.bind(1, m.fingerprint);
        if (series.step()) m.series = static_cast<std::size_t>(series.integer(0));
        commits.reset();
        commits.bind(1, m.fingerprint);
        while (commits.step())
            m.commits.push_back(
                {commits.text(0), commits.text(1), commits.text(2), static_cast<std::size_t>(commits.integer(3))});
        out.push_back(std::move(m));
    }
    return out;
}

}  // namespace suite
