// Forward-mode automatic differentiation: a dual number x + dx e with e^2 = 0. Running the
// runtime's templates on Dual<T> differentiates the value algorithms themselves along one
// direction, an algebra independent of the analytical derivative algorithms.
#pragma once

#include <cmath>

namespace dyngen::test {

template <class T>
struct Dual {
  T x{}, dx{};
  Dual() = default;
  Dual(T value, T derivative) : x(value), dx(derivative) {}
  explicit Dual(T value) : x(value) {}
  explicit Dual(int value) : x(T(value)) {}
};

template <class T> Dual<T> operator+(const Dual<T>& a, const Dual<T>& b) { return {a.x + b.x, a.dx + b.dx}; }
template <class T> Dual<T> operator-(const Dual<T>& a, const Dual<T>& b) { return {a.x - b.x, a.dx - b.dx}; }
template <class T> Dual<T> operator-(const Dual<T>& a) { return {-a.x, -a.dx}; }
template <class T> Dual<T> operator*(const Dual<T>& a, const Dual<T>& b) {
  return {a.x * b.x, a.dx * b.x + a.x * b.dx};
}
template <class T> Dual<T> operator/(const Dual<T>& a, const Dual<T>& b) {
  return {a.x / b.x, (a.dx * b.x - a.x * b.dx) / (b.x * b.x)};
}
template <class T> Dual<T> sin(const Dual<T>& a) { return {std::sin(a.x), a.dx * std::cos(a.x)}; }
template <class T> Dual<T> cos(const Dual<T>& a) { return {std::cos(a.x), -a.dx * std::sin(a.x)}; }

}  // namespace dyngen::test
