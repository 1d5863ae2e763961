// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/sweep_interpolation.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace ramiform::detail::sweep {

void Weights::add(int i, double wi, double dwi) {
  for (int k = 0; k < count; ++k) {
    if (index[k] == i) {
      w[k] += wi;
      dw[k] += dwi;
      return;
    }
  }
  index[count] = i;
  w[count] = wi;
  dw[count] = dwi;
  ++count;
}

Interpolator::Interpolator(std::vector<double> s, SkinInterpolation kind)
    : s_(std::move(s)), kind_(kind) {
  const int m = static_cast<int>(s_.size());
  quad_first_.assign(std::max(m - 1, 0), 0);
  for (int k = 0; k + 1 < m && m >= 3; ++k) {
    const bool has_left = k >= 1, has_right = k + 2 <= m - 1;
    if (has_left && has_right) {
      quad_first_[k] = s_[k + 2] - s_[k] < s_[k + 1] - s_[k - 1] ? k : k - 1;
    } else {
      quad_first_[k] = has_left ? k - 1 : k;
    }
  }
  lebesgue_ = 1;
  for (int k = 0; k + 1 < m; ++k) lebesgue_ = std::max(lebesgue_, interval_lebesgue(k));
}

// On interval k each weight is a polynomial of degree <= 3 in u = (s - s_k) / h; its largest
// |value| is at most the largest |Bernstein coefficient|, computed from its values at u = 0,
// 1/3, 2/3, 1.
double Interpolator::interval_lebesgue(int k) const {
  std::map<int, std::array<double, 4>> values;
  for (int i = 0; i < 4; ++i) {
    Weights w;
    interval_weights(k, s_[k] + (s_[k + 1] - s_[k]) * i / 3.0, w);
    for (int c = 0; c < w.count; ++c) {
      auto [it, fresh] = values.try_emplace(w.index[c], std::array<double, 4>{0, 0, 0, 0});
      it->second[i] = w.w[c];
    }
  }
  double sum = 0;
  for (const auto& [idx, f] : values) {
    const double b1 = (-5 * f[0] + 18 * f[1] - 9 * f[2] + 2 * f[3]) / 6;
    const double b2 = (2 * f[0] - 9 * f[1] + 18 * f[2] - 5 * f[3]) / 6;
    sum += std::max({std::abs(f[0]), std::abs(b1), std::abs(b2), std::abs(f[3])});
  }
  return sum;
}

Weights Interpolator::at(double s) const {
  Weights out;
  const int m = static_cast<int>(s_.size());
  if (m == 1 || s <= s_.front()) {
    out.add(0, 1, 0);
    return out;
  }
  if (s >= s_.back()) {
    out.add(m - 1, 1, 0);
    return out;
  }
  const int k = static_cast<int>(std::upper_bound(s_.begin(), s_.end(), s) - s_.begin()) - 1;
  interval_weights(k, s, out);
  return out;
}

void Interpolator::interval_weights(int k, double s, Weights& out) const {
  const int m = static_cast<int>(s_.size());
  const double a = s_[k], h = s_[k + 1] - a;
  const double u = (s - a) / h;
  if (kind_ == SkinInterpolation::kLinear || (kind_ == SkinInterpolation::kQuadratic && m < 3)) {
    out.add(k, 1 - u, -1 / h);
    out.add(k + 1, u, 1 / h);
    return;
  }
  if (kind_ == SkinInterpolation::kQuadratic) {
    const int f = quad_first_[k];
    const double x[3] = {s_[f], s_[f + 1], s_[f + 2]};
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, l = (i + 2) % 3;
      const double den = (x[i] - x[j]) * (x[i] - x[l]);
      out.add(f + i, (s - x[j]) * (s - x[l]) / den, ((s - x[j]) + (s - x[l])) / den);
    }
    return;
  }
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u;
  const double h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  const double dh00 = 6 * u2 - 6 * u, dh10 = 3 * u2 - 4 * u + 1;
  const double dh01 = -6 * u2 + 6 * u, dh11 = 3 * u2 - 2 * u;
  out.add(k, h00, dh00 / h);
  out.add(k + 1, h01, dh01 / h);
  // Term h10 · h · m_k: weight h·h10·c, derivative d/ds = dh10 · c (the 1/h and h cancel).
  add_slope(k, h * h10, dh10, out);
  add_slope(k + 1, h * h11, dh11, out);
}

// Adds f · m_i (and df · m_i) where the slope m_i at node i is a combination of the node
// values: the secant at an end, the derivative of the three-point parabola inside.
void Interpolator::add_slope(int i, double f, double df, Weights& out) const {
  const int m = static_cast<int>(s_.size());
  if (i == 0 || i == m - 1) {
    const int a = i == 0 ? 0 : m - 2;
    const double h = s_[a + 1] - s_[a];
    out.add(a, -f / h, -df / h);
    out.add(a + 1, f / h, df / h);
    return;
  }
  const double h0 = s_[i] - s_[i - 1], h1 = s_[i + 1] - s_[i];
  const double cm = -h1 / (h0 * (h0 + h1));
  const double cp = h0 / (h1 * (h0 + h1));
  const double c0 = (h1 / h0 - h0 / h1) / (h0 + h1);
  out.add(i - 1, f * cm, df * cm);
  out.add(i, f * c0, df * c0);
  out.add(i + 1, f * cp, df * cp);
}

}  // namespace ramiform::detail::sweep
