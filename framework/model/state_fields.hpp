#pragma once
// One table per state struct (GridPoint, Zone, Block, Contact, and the Model's own scalars) listing
// its plain per-item fields: name, element type, width and how to get and set the member. Whatever
// moves the state in bulk walks these tables instead of naming every member again: the checkpoint
// writer and reader (framework/io/checkpoint.cpp) use the names as dataset and attribute names, so
// a field added here is written and read back in the same way. The tables live in the model layer
// so that the parallel layer can pack the same fields for MPI.
//
// What is not a plain per-item field stays with its user: block names and the ragged boundary loops
// and rest offsets, the contact store's joint models and assignments.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#include "framework/model/model.hpp"

namespace rockdem::fields {

// Element types a field is stored as (the checkpoint maps them to HDF5 native types).
enum class Scalar : std::uint8_t { f64, i64, i32, u8 };

constexpr std::size_t size_of(Scalar s) {
  switch (s) {
    case Scalar::f64:
    case Scalar::i64: return 8;
    case Scalar::i32: return 4;
    case Scalar::u8: return 1;
  }
  return 0;
}

// identity: describes what the item is (ids, topology); a restore checks it against the model
// built from the case instead of overwriting it. state: evolves during a run and is restored.
enum class Role : std::uint8_t { state, identity };

template <class Item>
struct Field {
  const char* name;
  Scalar type;
  std::size_t width;  // values per item: 1 for scalars, 2 for Vec2, 3 for Voigt3, bytes for raw state
  Role role;
  void (*get)(const Item&, std::byte* out);  // writes width * size_of(type) bytes
  void (*set)(Item&, const std::byte* in);   // reads as many

  constexpr std::size_t bytes() const { return width * size_of(type); }
};

// How a member type is stored: element type, width, and the conversion both ways.
template <class M>
struct Codec;

// A scalar member stored as one element, converted both ways: long (Model::step) as 64 bits
// whatever the platform's long, bool as one byte 0 or 1 (any non-zero byte reads as true).
template <class M, class E, Scalar S>
struct ScalarCodec {
  using Element = E;
  static constexpr Scalar type = S;
  static constexpr std::size_t width = 1;
  static void store(const M& v, Element* out) { out[0] = static_cast<Element>(v); }
  static void load(M& v, const Element* in) { v = static_cast<M>(in[0]); }
};
template <>
struct Codec<double> : ScalarCodec<double, double, Scalar::f64> {};
template <>
struct Codec<long> : ScalarCodec<long, std::int64_t, Scalar::i64> {};
template <>
struct Codec<std::int32_t> : ScalarCodec<std::int32_t, std::int32_t, Scalar::i32> {};
template <>
struct Codec<std::uint8_t> : ScalarCodec<std::uint8_t, std::uint8_t, Scalar::u8> {};  // Block::prescribed bit mask
template <>
struct Codec<bool> : ScalarCodec<bool, std::uint8_t, Scalar::u8> {};
template <>
struct Codec<BlockId> {  // stored as its value
  using Element = std::int32_t;
  static constexpr Scalar type = Scalar::i32;
  static constexpr std::size_t width = 1;
  static void store(const BlockId& v, Element* out) { out[0] = id_value(v); }
  static void load(BlockId& v, const Element* in) { v = BlockId{in[0]}; }
};

// Fixed-size vectors (Vec2, Voigt3) and arrays (zone connectivity): one element per component.
template <class V, class E, Scalar S, std::size_t N>
struct ComponentCodec {
  using Element = E;
  static constexpr Scalar type = S;
  static constexpr std::size_t width = N;
  static void store(const V& v, Element* out) {
    for (std::size_t k = 0; k < N; ++k) out[k] = v[static_cast<decltype(v.size())>(k)];
  }
  static void load(V& v, const Element* in) {
    for (std::size_t k = 0; k < N; ++k) v[static_cast<decltype(v.size())>(k)] = in[k];
  }
};
template <>
struct Codec<Vec2> : ComponentCodec<Vec2, double, Scalar::f64, 2> {};
template <>
struct Codec<Voigt3> : ComponentCodec<Voigt3, double, Scalar::f64, 3> {};
template <>
struct Codec<std::array<int, 3>> : ComponentCodec<std::array<int, 3>, std::int32_t, Scalar::i32, 3> {};

// Opaque state (rock-material and joint-law history): its bytes as they are.
template <std::size_t N>
struct Codec<std::array<std::byte, N>> {
  using Element = std::uint8_t;
  static constexpr Scalar type = Scalar::u8;
  static constexpr std::size_t width = N;
  static void store(const std::array<std::byte, N>& v, Element* out) { std::memcpy(out, v.data(), N); }
  static void load(std::array<std::byte, N>& v, const Element* in) { std::memcpy(v.data(), in, N); }
};

template <>
struct Codec<ContactKey> {  // point block, point local index, other block, side
  using Element = std::int32_t;
  static constexpr Scalar type = Scalar::i32;
  static constexpr std::size_t width = 4;
  static void store(const ContactKey& k, Element* out) {
    out[0] = id_value(k.point_block);
    out[1] = k.point_local;
    out[2] = id_value(k.other_block);
    out[3] = k.side;
  }
  static void load(ContactKey& k, const Element* in) { k = {BlockId{in[0]}, in[1], BlockId{in[2]}, in[3]}; }
};

// A field from a captureless accessor `[](auto& item) -> auto& { return item.member; }`; the
// element type and width follow from the member's type, so they cannot disagree with it. The
// values pass through a local array because the byte buffers need not be aligned.
template <class Item, class Ref>
constexpr Field<Item> field(const char* name, Ref, Role role = Role::state) {
  using M = std::remove_cvref_t<decltype(Ref{}(std::declval<Item&>()))>;
  using C = Codec<M>;
  using E = typename C::Element;
  static_assert(sizeof(E) == size_of(C::type));
  return {name, C::type, C::width, role,
          [](const Item& item, std::byte* out) {
            std::array<E, C::width> v{};
            C::store(Ref{}(item), v.data());
            std::memcpy(out, v.data(), sizeof v);
          },
          [](Item& item, const std::byte* in) {
            std::array<E, C::width> v{};
            std::memcpy(v.data(), in, sizeof v);
            C::load(Ref{}(item), v.data());
          }};
}

#define ROCKDEM_MEMBER(expr) [](auto& it) -> auto& { return it.expr; }

// The order of each table is the order of writing.
inline constexpr Field<GridPoint> kGridPointFields[] = {
    field<GridPoint>("x0", ROCKDEM_MEMBER(x0)),
    field<GridPoint>("x", ROCKDEM_MEMBER(x)),
    field<GridPoint>("v", ROCKDEM_MEMBER(v)),
    field<GridPoint>("f", ROCKDEM_MEMBER(f)),
    field<GridPoint>("mass", ROCKDEM_MEMBER(mass)),
    field<GridPoint>("stiffness", ROCKDEM_MEMBER(stiffness)),
    field<GridPoint>("block", ROCKDEM_MEMBER(block), Role::identity),
    field<GridPoint>("local", ROCKDEM_MEMBER(local), Role::identity),
    field<GridPoint>("fixed_x", ROCKDEM_MEMBER(fixed_x)),
    field<GridPoint>("fixed_y", ROCKDEM_MEMBER(fixed_y)),
    field<GridPoint>("prescribed", ROCKDEM_MEMBER(prescribed)),
};

inline constexpr Field<Zone> kZoneFields[] = {
    field<Zone>("n", ROCKDEM_MEMBER(n), Role::identity),
    field<Zone>("area", ROCKDEM_MEMBER(area)),
    field<Zone>("stress", ROCKDEM_MEMBER(stress)),
    field<Zone>("szz", ROCKDEM_MEMBER(szz)),
    field<Zone>("strain", ROCKDEM_MEMBER(strain)),
    field<Zone>("material", ROCKDEM_MEMBER(material), Role::identity),
    field<Zone>("material_state", ROCKDEM_MEMBER(material_state)),
};

// Besides these: name, boundary loop and rest offsets (not fixed-width).
inline constexpr Field<Block> kBlockFields[] = {
    field<Block>("id", ROCKDEM_MEMBER(id), Role::identity),
    field<Block>("rigid", ROCKDEM_MEMBER(rigid), Role::identity),
    field<Block>("group", ROCKDEM_MEMBER(group), Role::identity),
    field<Block>("first_gp", ROCKDEM_MEMBER(first_gp), Role::identity),
    field<Block>("n_gp", ROCKDEM_MEMBER(n_gp), Role::identity),
    field<Block>("first_zone", ROCKDEM_MEMBER(first_zone), Role::identity),
    field<Block>("n_zone", ROCKDEM_MEMBER(n_zone), Role::identity),
    field<Block>("density", ROCKDEM_MEMBER(density)),
    field<Block>("mass", ROCKDEM_MEMBER(mass)),
    field<Block>("inertia", ROCKDEM_MEMBER(inertia)),
    field<Block>("xc0", ROCKDEM_MEMBER(xc0)),
    field<Block>("xc", ROCKDEM_MEMBER(xc)),
    field<Block>("vc", ROCKDEM_MEMBER(vc)),
    field<Block>("fc", ROCKDEM_MEMBER(fc)),
    field<Block>("theta", ROCKDEM_MEMBER(theta)),
    field<Block>("omega", ROCKDEM_MEMBER(omega)),
    field<Block>("moment", ROCKDEM_MEMBER(moment)),
    field<Block>("mass_scale", ROCKDEM_MEMBER(mass_scale)),
    field<Block>("fixed", ROCKDEM_MEMBER(fixed)),
    field<Block>("prescribed", ROCKDEM_MEMBER(prescribed)),
};

// Contacts have no identity fields: they are restored as a whole and then checked for references
// to gridpoints, blocks and joint models the model does not have. Their joint-law states are
// not a field of Contact but the store's ContactStates, as wide as its joint models need: the
// checkpoint and the processes' exchange add them after these.
inline constexpr Field<Contact> kContactFields[] = {
    field<Contact>("key", ROCKDEM_MEMBER(key)),
    field<Contact>("point", ROCKDEM_MEMBER(point)),
    field<Contact>("other", ROCKDEM_MEMBER(other)),
    field<Contact>("point_loop", ROCKDEM_MEMBER(point_loop)),
    field<Contact>("face_mode", ROCKDEM_MEMBER(face_mode)),
    field<Contact>("edge", ROCKDEM_MEMBER(edge)),
    field<Contact>("s", ROCKDEM_MEMBER(s)),
    field<Contact>("normal", ROCKDEM_MEMBER(normal)),
    field<Contact>("length", ROCKDEM_MEMBER(length)),
    field<Contact>("span", ROCKDEM_MEMBER(span)),
    field<Contact>("overlap", ROCKDEM_MEMBER(overlap)),
    field<Contact>("joint", ROCKDEM_MEMBER(joint)),
    field<Contact>("pretouch_gap", ROCKDEM_MEMBER(pretouch_gap)),
    field<Contact>("pending_closure", ROCKDEM_MEMBER(pending_closure)),
    field<Contact>("fresh", ROCKDEM_MEMBER(fresh)),
    field<Contact>("sigma_n", ROCKDEM_MEMBER(response.sigma_n)),
    field<Contact>("tau", ROCKDEM_MEMBER(response.tau)),
    field<Contact>("kn", ROCKDEM_MEMBER(response.kn)),
    field<Contact>("ks", ROCKDEM_MEMBER(response.ks)),
    field<Contact>("u_s", ROCKDEM_MEMBER(response.u_s)),
    field<Contact>("u_n", ROCKDEM_MEMBER(response.u_n)),
    field<Contact>("dilation", ROCKDEM_MEMBER(response.dilation)),
    field<Contact>("dissipated", ROCKDEM_MEMBER(response.dissipated)),
    field<Contact>("slipping", ROCKDEM_MEMBER(response.slipping)),
    field<Contact>("open", ROCKDEM_MEMBER(response.open)),
};

// The Model's own scalars (all of width 1; gravity by component).
inline constexpr Field<Model> kModelFields[] = {
    field<Model>("time", ROCKDEM_MEMBER(time)),
    field<Model>("step", ROCKDEM_MEMBER(step)),
    field<Model>("thickness", ROCKDEM_MEMBER(thickness), Role::identity),
    field<Model>("gravity_x", ROCKDEM_MEMBER(gravity.x())),
    field<Model>("gravity_y", ROCKDEM_MEMBER(gravity.y())),
};

#undef ROCKDEM_MEMBER

}  // namespace rockdem::fields
