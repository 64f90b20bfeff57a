// Every registered scheme (scheme_choices(), so a scheme added to sim/scene/scheme_registry.hpp
// is walked without an edit here) through the same checks, quadratic kernel, 2D and 3D: P2G
// conserves mass, linear and angular momentum, G2P linear momentum; a scheme with C reproduces an
// affine field through P2G and G2P; one force-free particle keeps its velocity field (Sec 5.4 of
// Jiang et al. 2017); and the one-particle check with the other kernels.
#include "tests/mpm/schemes/scheme_fixture.hpp"

namespace apiclab {
namespace {

using test::Change;
using test::kRoundOff;
using test::scheme_scene;

TEST(SchemeProperties, EverySchemeConservesMomentum) {
  for (const auto& c : scheme_choices()) {
    SCOPED_TRACE(c.key);
    const std::string key(c.key);
    const Change p2g2 = test::p2g_change<2>(scheme_scene(2, key, "quadratic"), 44);
    const Change p2g3 = test::p2g_change<3>(scheme_scene(3, key, "quadratic"), 45);
    const Change g2p2 = test::g2p_change<2>(scheme_scene(2, key, "quadratic"), 9, 0.01, 0.5);
    const Change g2p3 = test::g2p_change<3>(scheme_scene(3, key, "quadratic"), 10, 0.01, 0.5);
    std::printf(
        "[ %-7s ] relative |dp|, |dL|: P2G %.2g %.2g (2D) %.2g %.2g (3D); G2P |dp| %.2g "
        "(2D) %.2g (3D)\n",
        key.c_str(), p2g2.p, p2g2.L, p2g3.p, p2g3.L, g2p2.p, g2p3.p);
    EXPECT_LE(p2g2.p, kRoundOff);
    EXPECT_LE(p2g2.L, kRoundOff);
    EXPECT_LE(p2g3.p, kRoundOff);
    EXPECT_LE(p2g3.L, kRoundOff);
    EXPECT_LE(g2p2.p, kRoundOff);
    EXPECT_LE(g2p3.p, kRoundOff);
  }
}

TEST(SchemeProperties, EveryAffineSchemeRoundTripsAnAffineField) {
  int affine = 0;
  for (const auto& c : scheme_choices()) {
    if (!is_affine(c.value)) continue;
    ++affine;
    test::particle_affine_round_trip<2>(std::string(c.key), "quadratic");
    test::particle_affine_round_trip<3>(std::string(c.key), "quadratic");
  }
  EXPECT_GE(affine, 2);  // APIC and RPIC at least: the walk is not empty
}

TEST(SchemeProperties, EverySchemeKeepsOneParticle) {
  for (const auto& c : scheme_choices()) {
    test::one_particle<2>(std::string(c.key), "quadratic");
    test::one_particle<3>(std::string(c.key), "quadratic");
  }
}

// The other kernels of the schemes that run them.
TEST(SchemeProperties, OneParticleOtherKernels) {
  for (const char* s : {"apic", "asflip", "xpic", "tpic"}) {
    test::one_particle<2>(s, "cubic");
    test::one_particle<3>(s, "cubic");
  }
  test::one_particle<2>("tpic", "linear");
  test::one_particle<3>("tpic", "linear");
}

}  // namespace
}  // namespace apiclab
