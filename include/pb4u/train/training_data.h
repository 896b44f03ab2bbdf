#pragma once
// Loads what training samples from out of a dataset written by `pb4u generate`.
#include "pb4u/train/train_config.h"
#include "pb4u/train/trainer.h"

namespace pb4u {

// Bodies, the garments at data.levels (filtered by data.garments) and the training split of
// the motions. Throws pb4u::Error naming the dataset file on any problem.
TrainingData load_training_data(const TrainDataConfig& data);

}  // namespace pb4u
