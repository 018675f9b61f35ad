// The number of fields of an aggregate, at compile time: the most initializers it accepts. Tests
// use it to notice a field added to a spec struct that the family's schema does not know yet.
#pragma once

#include <cstddef>
#include <type_traits>
#include <utility>

namespace brdfbake::test {

namespace detail {

// The overload choice between AnyField's conversion and a converting constructor (std::optional)
// is what the count relies on; GCC's -Wconversion remarks on it.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#endif

// Converts to any type (a field's initializer).
struct AnyField {
  template <class T>
  operator T() const;  // never defined: used in unevaluated contexts only
};

template <class T, class Indices, class = void>
struct InitializableWith : std::false_type {};

template <class T, std::size_t... I>
struct InitializableWith<T, std::index_sequence<I...>, std::void_t<decltype(T{(void(I), AnyField{})...})>>
    : std::true_type {};

template <class T, std::size_t N>
constexpr std::size_t count_fields() {
  if constexpr (InitializableWith<T, std::make_index_sequence<N + 1>>::value)
    return count_fields<T, N + 1>();
  else
    return N;
}

#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace detail

template <class T>
constexpr std::size_t field_count() {
  static_assert(std::is_aggregate_v<T>, "field_count needs an aggregate");
  return detail::count_fields<T, 0>();
}

}  // namespace brdfbake::test
