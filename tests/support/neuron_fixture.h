// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// A generated neuron in SWC, like a NeuroMorpho.Org reconstruction: a soma, primary dendrites
/// that branch and taper down to 0.2 um, an axon with collaterals; micrometres, coordinates and
/// radii rounded to 0.01 um as real files are. All randomness flows through ramiform::Rng, so
/// the text is identical on every platform.

#include <cstdint>
#include <string>

namespace ramiform::test {

/// How the generated neuron writes its soma (docs/formats.md, "SWC").
enum class NeuronSoma {
  kSinglePoint,  ///< one type-1 sample of radius `soma_radius`
  kThreePoint,   ///< NeuroMorpho: centre plus two samples at -+ soma_radius along y
  kContour,      ///< an outline of 16 samples (a chain) in the xy plane, at `soma_radius` from 0
  kCylinders,    ///< a stack of 7 overlapping samples along z (a spindle, widest in the middle)
};

/// Options of neuron_swc().
struct NeuronOptions {
  std::uint64_t seed = 1;
  int dendrites = 6;  ///< primary dendrites (4..8 in the tests); the first is apical (type 4)
  /// About this many samples in all, within 10 % (the branch lengths scale to it).
  int target_samples = 3000;
  double soma_radius = 8.0;  ///< um
  NeuronSoma soma = NeuronSoma::kSinglePoint;
  bool shuffle = false;  ///< write the samples in a random order (parents may follow children)
  int extra_trees = 0;   ///< further unconnected neurite fragments (roots without a soma)
};

/// Facts about the generated neuron, for tests.
struct NeuronFacts {
  int samples = 0;
  int soma_samples = 0;
  int roots = 0;          ///< samples with parent -1 (1 + extra_trees)
  double min_radius = 0;  ///< smallest neurite radius written
  double max_neurite_radius = 0;
};

/// The SWC text of a generated neuron (header comments, one sample per line, "%.2f" numbers).
/// Throws std::invalid_argument unless 1 <= dendrites <= 12, target_samples >= 200,
/// soma_radius >= 1 and extra_trees >= 0.
[[nodiscard]] std::string neuron_swc(const NeuronOptions& options, NeuronFacts* facts = nullptr);

}  // namespace ramiform::test
