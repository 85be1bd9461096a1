#pragma once
// Small POD 3-vector usable in device code. Deliberately minimal: no constructors beyond
// aggregate init, so arrays of Vec3 stay trivially copyable between host and device.
#include <cmath>

#include "millsim/core/hd.hpp"

namespace millsim::core {

template <class T>
struct Vec3 {
  T x, y, z;
};

template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> operator+(Vec3<T> a, Vec3<T> b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> operator-(Vec3<T> a, Vec3<T> b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> operator-(Vec3<T> a) {
  return {-a.x, -a.y, -a.z};
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> operator*(T s, Vec3<T> a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> operator*(Vec3<T> a, T s) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T>& operator+=(Vec3<T>& a, Vec3<T> b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T>& operator-=(Vec3<T>& a, Vec3<T> b) {
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
template <class T>
MILLSIM_HD MILLSIM_INLINE T dot(Vec3<T> a, Vec3<T> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
MILLSIM_HD MILLSIM_INLINE T norm2(Vec3<T> a) {
  return dot(a, a);
}
template <class T>
MILLSIM_HD MILLSIM_INLINE T norm(Vec3<T> a) {
  return std::sqrt(dot(a, a));
}

template <class T>
MILLSIM_HD MILLSIM_INLINE Vec3<T> zero3() {
  return {T(0), T(0), T(0)};
}

}  // namespace millsim::core
