// The transfer schemes: each is one file under sim/mpm/schemes/ and one line here. Its key, name,
// help, source, colour and traits are read from its file by the choice registry (scheme_choices),
// the docs' scheme table (`apiclab docs schemes`), the palette and the fast step (with_scheme).
#pragma once
#include <array>
#include <cstddef>
#include <string_view>
#include <tuple>
#include <utility>

#include "sim/mpm/schemes/apic.hpp"
#include "sim/mpm/schemes/asflip.hpp"
#include "sim/mpm/schemes/flip.hpp"
#include "sim/mpm/schemes/mls.hpp"
#include "sim/mpm/schemes/pic.hpp"
#include "sim/mpm/schemes/polypic.hpp"
#include "sim/mpm/schemes/rpic.hpp"
#include "sim/mpm/schemes/tpic.hpp"
#include "sim/mpm/schemes/xpic.hpp"

namespace apiclab {

enum class Scheme { pic, flip, apic, rpic, mls, asflip, xpic, tpic, polypic };

template <Scheme S, class File>
struct SchemeRow {
  static constexpr Scheme id = S;
  using type = File;
};

// One line per scheme, in the enum's order (the order of help texts, GUI lists and colours).
// clang-format off
using SchemeRows = std::tuple<
    SchemeRow<Scheme::pic, schemes::Pic>,
    SchemeRow<Scheme::flip, schemes::Flip>,
    SchemeRow<Scheme::apic, schemes::Apic>,
    SchemeRow<Scheme::rpic, schemes::Rpic>,
    SchemeRow<Scheme::mls, schemes::Mls>,
    SchemeRow<Scheme::asflip, schemes::Asflip>,
    SchemeRow<Scheme::xpic, schemes::Xpic>,
    SchemeRow<Scheme::tpic, schemes::Tpic>,
    SchemeRow<Scheme::polypic, schemes::PolyPic>>;
// clang-format on

inline constexpr int kSchemeCount = int(std::tuple_size_v<SchemeRows>);

// Scheme S's file: scheme_t<Scheme::apic> is schemes::Apic.
template <Scheme S>
using scheme_t = typename std::tuple_element_t<std::size_t(S), SchemeRows>::type;

// A scheme as people and tools read it.
struct SchemeInfo {
  Scheme value;
  std::string_view key, name, help, source, conserves;
  int colour;
  bool affine, blends_flip, force_in_affine;
};

namespace detail {
template <std::size_t I>
constexpr SchemeInfo scheme_info_at() {
  using Row = std::tuple_element_t<I, SchemeRows>;
  using F = typename Row::type;
  static_assert(std::size_t(Row::id) == I, "SchemeRows lists the schemes in the enum's order");
  return {Row::id,      F::key,    F::name,   F::help,      F::source,
          F::conserves, F::colour, F::affine, F::reads_old, F::force_in_affine};
}
template <std::size_t... I>
constexpr std::array<SchemeInfo, sizeof...(I)> scheme_infos(std::index_sequence<I...>) {
  return {scheme_info_at<I>()...};
}
}  // namespace detail

inline constexpr std::array<SchemeInfo, kSchemeCount> kSchemes =
    detail::scheme_infos(std::make_index_sequence<kSchemeCount>{});

constexpr const SchemeInfo& scheme_info(Scheme s) { return kSchemes[std::size_t(s)]; }

// Carries the affine matrix C_p: P2G transfers v_p + C_p (x_i − x_p) (eq 24).
constexpr bool is_affine(Scheme s) { return scheme_info(s).affine; }

// The schemes that read solver.flip_alpha: those that read Σ w vⁿ, FLIP (eq 3) and ASFLIP.
constexpr bool blends_flip(Scheme s) { return scheme_info(s).blends_flip; }

}  // namespace apiclab
