#pragma once
// Weight averaging of trained models (`pb4u export --checkpoint A --checkpoint B ...`): the
// parameters of several files of one architecture, mixed with given weights. Two uses:
//  - the tail of a run (SWA-style): checkpoints a few hundred steps apart differ by up to 10x
//    on a hanging scene (docs/training.md); their mean is one smoother model;
//  - interpolating a fine-tune with the model it started from (base + a (tuned - base)),
//    which keeps what the base did well while taking part of what the fine-tune learned.
// Normaliser statistics and calibration are buffers, not learned: they must be the same in
// every file (a run's checkpoints after warm-up, or a fine-tune and the model it started from).
#include <string>
#include <vector>

#include "pb4u/model/model_file.h"

namespace pb4u {

// Sum over i of weights[i] * parameters of models[i], into a copy of models[0] (its config,
// step and buffers). weights empty = equal weights; otherwise one per model, any reals whose
// sum is 1 (within 1e-6; a weight may be negative, to extrapolate). Throws a one-line
// pb4u::Error naming the file when models differ in kind or shape, or their buffers differ.
ModelFile average_models(const std::vector<ModelFile>& models, const std::vector<double>& weights);

}  // namespace pb4u
