// The particle snapshot writer (kernels/mpm/vtk.hpp): base64 against RFC 4648's vectors, a .vtu
// whose arrays decode back to the particles' values bit for bit, and a .pvd that lists the
// snapshots with times that read back exactly. meshio's side: tests/cli/mpm_cli_test.cpp.
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/mpm/vtk.hpp"

using namespace suite::mpm;

namespace {

std::string b64(const std::string& s) { return base64(s.data(), s.size()); }

std::string unbase64(const std::string& text) {
    const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::uint32_t acc = 0;
    int bits = 0;
    for (char c : text) {
        if (c == '=') break;
        acc = (acc << 6) | static_cast<std::uint32_t>(alphabet.find(c));
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += static_cast<char>((acc >> bits) & 0xff);
        }
    }
    return out;
}

// The decoded bytes (after the UInt64 count) of each DataArray, by Name.
std::map<std::string, std::string> arrays(const std::string& vtu) {
    std::map<std::string, std::string> out;
    for (std::size_t at = 0; (at = vtu.find("<DataArray", at)) != std::string::npos;) {
        const std::size_t name = vtu.find("Name=\"", at) + 6;
        const std::string key = vtu.substr(name, vtu.find('"', name) - name);
        const std::size_t start = vtu.find('>', at) + 2, end = vtu.find("\n</DataArray>", start);
        const std::string raw = unbase64(vtu.substr(start, end - start));
        std::uint64_t bytes = 0;
        std::memcpy(&bytes, raw.data(), sizeof bytes);
        EXPECT_EQ(bytes + sizeof bytes, raw.size()) << key;
        out[key] = raw.substr(sizeof bytes);
        at = end;
    }
    return out;
}

template <class T>
std::vector<T> values(const std::string& bytes) {
    std::vector<T> v(bytes.size() / sizeof(T));
    std::memcpy(v.data(), bytes.data(), bytes.size());
    return v;
}

}  // namespace

TEST(ParticlesVtk, Base64MatchesTheRfcVectors) {
    EXPECT_EQ(b64(""), "");
    EXPECT_EQ(b64("f"), "Zg==");
    EXPECT_EQ(b64("fo"), "Zm8=");
    EXPECT_EQ(b64("foo"), "Zm9v");
    EXPECT_EQ(b64("foob"), "Zm9vYg==");
    EXPECT_EQ(b64("fooba"), "Zm9vYmE=");
    EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
    const std::string all = [] {
        std::string s;
        for (int i = 0; i < 256; ++i) s += static_cast<char>(i);
        return s;
    }();
    EXPECT_EQ(unbase64(b64(all)), all);
}

TEST(ParticlesVtk, ArraysDecodeToTheParticlesExactly) {
    Particles p;
    p.resize(3);
    for (std::size_t i = 0; i < 3; ++i) {
        p.x[i] = 0.1 * static_cast<double>(i) + 1.0 / 3, p.y[i] = std::nextafter(0.5, 1.0),
        p.z[i] = 1e-300 * static_cast<double>(i);
        p.vx[i] = -1.5, p.vy[i] = 2.0 / 7, p.vz[i] = static_cast<double>(i);
        for (int k = 0; k < 6; ++k) p.stress[k][i] = 10.0 * k + static_cast<double>(i) / 9;
        p.volume[i] = 1e-6 / 3, p.mass[i] = 1e-3 / 3;
        p.id[i] = static_cast<std::uint32_t>(2 - i);
    }
    const std::string vtu = particles_vtu(p);
    EXPECT_NE(vtu.find("NumberOfPoints=\"3\" NumberOfCells=\"3\""), std::string::npos);
    EXPECT_NE(vtu.find("ComponentName0=\"xx\""), std::string::npos);
    EXPECT_NE(vtu.find("ComponentName5=\"zx\""), std::string::npos);
    const auto a = arrays(vtu);
    EXPECT_EQ(values<double>(a.at("position")),
              (std::vector<double>{p.x[0], p.y[0], p.z[0], p.x[1], p.y[1], p.z[1], p.x[2], p.y[2], p.z[2]}));
    EXPECT_EQ(values<double>(a.at("velocity"))[7], p.vy[2]);
    EXPECT_EQ(values<double>(a.at("stress"))[6 * 2 + 4], p.stress[4][2]);
    EXPECT_EQ(values<std::uint32_t>(a.at("id")), p.id);
    EXPECT_EQ(values<double>(a.at("volume")), p.volume);
    EXPECT_EQ(values<double>(a.at("mass")), p.mass);
    EXPECT_EQ(values<std::int64_t>(a.at("connectivity")), (std::vector<std::int64_t>{0, 1, 2}));
    EXPECT_EQ(values<std::int64_t>(a.at("offsets")), (std::vector<std::int64_t>{1, 2, 3}));
    EXPECT_EQ(a.at("types"), std::string(3, '\1'));  // VTK_VERTEX
}

TEST(ParticlesVtk, CollectionListsTheSnapshotsWithTimesThatReadBack) {
    const double t = 0.1 + 0.2;  // 0.30000000000000004
    const std::string pvd = collection_pvd({{"particles_000000.vtu", 0}, {"particles_000050.vtu", t}});
    EXPECT_NE(pvd.find("type=\"Collection\""), std::string::npos);
    EXPECT_NE(pvd.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"particles_000000.vtu\"/>"),
              std::string::npos)
        << pvd;
    const std::size_t at = pvd.find("timestep=\"", pvd.find("particles_000000")) + 10;
    EXPECT_EQ(std::stod(pvd.substr(at)), t) << pvd;
}
