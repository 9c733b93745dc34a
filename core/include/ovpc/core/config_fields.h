// Each Config states its settings once, beside its members, in a static member template
//
//   template <class C, class V>
//   static void VisitFields(C& c, V& v) {       // C is the Config or const Config
//     v.Field(OVPC_FIELD(c, max_scans), "scans", "paper: 20-30");
//     v.Choice(OVPC_FIELD(c, kernel), Choices<GhprKernel>{{"exponential", GhprKernel::kExponential}, ...}, "paper");
//     v.Section(OVPC_FIELD(c, ghpr), "the paper's hidden point removal");
//   }
//
// in the spirit of Drake's Serialize(Archive*) with DRAKE_NVP(field): the key is the field's own
// token, so it cannot drift from the struct; the default is the member initialiser; each field has a
// unit ("" when it has none) and a one-line reason. The YAML reader and writers (`ovpc run
// --print-config`, result.json), the preset check and any adapter a user writes (ROS parameters, a
// GUI) are visitors V with these three members:
//   Field(const char* key, T& value, const char* unit, const char* why)   double, int, unsigned,
//                                     bool, std::size_t, std::uint32_t, std::uint64_t, std::vector<double>
//   Choice(const char* key, E& value, Choices<E> choices, const char* why)  an enum by its names
//   Section(const char* key, Config& config, const char* why)          a nested Config
// A Config holds settings only, so every member is visited: CountMembers<Config>() (the aggregate's
// member count) equals CountFields<Config>(), which tests/core/config_fields_test.cc checks.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <type_traits>
#include <utility>

/// The key and the member of one field of `config`: `"name", config.name`.
#define OVPC_FIELD(config, name) #name, (config).name

namespace ovpc {

/// An enum's values by their names in files.
template <class E>
using Choices = std::initializer_list<std::pair<const char*, E>>;

/// Visits the settings of `config` (a Config with a static VisitFields) with `visitor`.
template <class C, class V>
void VisitFields(C& config, V& visitor) {
  std::remove_const_t<C>::VisitFields(config, visitor);
}

/// True for a type that declares its fields (has a static VisitFields).
template <class T, class = void>
struct HasFields : std::false_type {};

namespace internal {

/// Counts the fields a Config visits, sections as one.
struct FieldCounter {
  std::size_t count = 0;
  template <class T>
  void Field(const char*, T&, const char*, const char*) {
    ++count;
  }
  template <class E>
  void Choice(const char*, E&, Choices<E>, const char*) {
    ++count;
  }
  template <class C>
  void Section(const char*, C&, const char*) {
    ++count;
  }
};

/// Converts to any member type (the brace-initialisation counting trick).
struct AnyMember {
  template <class T>
  operator T() const;  // declared only: used in unevaluated contexts
};

template <class T, class Seq, class = void>
struct BraceConstructible : std::false_type {};
template <class T, std::size_t... I>
struct BraceConstructible<T, std::index_sequence<I...>,
                          std::void_t<decltype(T{(static_cast<void>(I), AnyMember{})...})>> : std::true_type {};

template <class T, std::size_t N>
constexpr std::size_t CountMembersFrom() {
  if constexpr (BraceConstructible<T, std::make_index_sequence<N + 1>>::value) {
    return CountMembersFrom<T, N + 1>();
  } else {
    return N;
  }
}

}  // namespace internal

template <class T>
struct HasFields<T, std::void_t<decltype(T::VisitFields(std::declval<T&>(), std::declval<internal::FieldCounter&>()))>>
    : std::true_type {};

/// The number of members of the aggregate T: the most initialisers `T{...}` takes.
template <class T>
constexpr std::size_t CountMembers() {
  static_assert(std::is_aggregate_v<T>, "a Config is an aggregate of its settings");
  return internal::CountMembersFrom<T, 0>();
}

/// The number of fields T's VisitFields declares (a section counts as one).
template <class T>
std::size_t CountFields() {
  T config{};
  internal::FieldCounter counter;
  VisitFields(config, counter);
  return counter.count;
}

}  // namespace ovpc
