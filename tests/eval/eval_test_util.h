#pragma once
// Helpers shared by the evaluation suites (evaluate, bench, score, stability).
#include <sstream>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/eval/evaluate.h"
#include "test_util.h"

namespace pb4u::test {

// configs/eval/tiny.yaml on the tiny dataset, with `sets` applied.
inline EvalConfig tiny_eval(std::vector<std::string> sets = {}) {
  sets.push_back("dataset=" + tiny_dataset());
  return load_config<EvalConfig>(kSource + "/configs/eval/tiny.yaml", sets);
}

// A CSV file's rows split at commas (the files under test quote no commas).
inline std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_file(path));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

}  // namespace pb4u::test
