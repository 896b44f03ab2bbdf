#include "pb4u/train/group_start.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

void agree_to_start(DistributedGroup& group, const std::string& problem, const std::string& config_yaml,
                    bool resume) {
  const std::string root_problem = group.broadcast_bytes(problem);
  if (!root_problem.empty())
    throw Error(group.is_root() ? root_problem : "rank 0 could not start the run: " + root_problem);
  // Ranks with different configs would train different things under one name; a --resume
  // on some ranks only would pair different collectives.
  torch::Tensor votes = torch::tensor({group.broadcast_bytes(config_yaml) == config_yaml ? 0L : 1L,
                                       resume ? 1L : 0L});
  group.all_reduce_sum(votes);
  const int64_t other_configs = votes[0].item<int64_t>(), resuming = votes[1].item<int64_t>();
  if (other_configs > 0)
    throw Error("rank " + std::to_string(group.rank()) + ": " + std::to_string(other_configs) +
                " rank(s) run another training config than rank 0; every rank must get the same --config and --set");
  if (resuming != 0 && resuming != group.world_size())
    throw Error("--resume: given to " + std::to_string(resuming) + " of " + std::to_string(group.world_size()) +
                " ranks; give it to every rank or to none");
}

void share_checkpoint(DistributedGroup& group, const std::string& root_bytes,
                      const std::function<void(const std::string& path)>& load) {
  const std::string bytes = group.broadcast_bytes(root_bytes);
  if (group.is_root()) return;
  namespace fs = std::filesystem;
  const std::string tmp = (fs::temp_directory_path() / ("pb4u_resume_rank" + std::to_string(group.rank()) + "_" +
                                                        std::to_string(::getpid()) + ".pt"))
                              .string();
  {
    AtomicFile file(tmp, /*binary=*/true);
    file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.commit();
  }
  try {
    load(tmp);
  } catch (...) {
    fs::remove(tmp);
    throw;
  }
  fs::remove(tmp);
}

void broadcast_module_state(DistributedGroup& group, torch::nn::Module& module) {
  for (auto& p : module.parameters()) {
    torch::Tensor data = p.detach();
    group.broadcast(data);
  }
  for (auto& b : module.buffers()) group.broadcast(b);
}

std::string read_binary_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, "cannot read checkpoint");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace pb4u
