#pragma once
// Data-parallel training's communication (issue 10): a group of `world_size` processes that
// all-reduce and broadcast tensors through LibTorch's c10d engine (Gloo over TCP; the ranks
// meet at a TCPStore that rank 0 serves at the master address). The c10d headers stay in
// distributed.cpp because their API moved between LibTorch 1.x and 2.x. A group of one rank
// opens no socket and every collective is the identity, so single-process training runs the
// same code.
#include <torch/types.h>

#include <memory>
#include <string>
#include <vector>

namespace pb4u {

struct DistributedOptions {
  int world_size = 1;
  int rank = 0;                               // 0 .. world_size-1; rank 0 serves the store
  std::string master = "127.0.0.1:29500";     // HOST:PORT of rank 0's rendezvous store
  double timeout_seconds = 300;               // s: the rendezvous and every collective
};

class DistributedGroup {
 public:
  // Joins the group: blocks until all ranks have joined. Throws pb4u::Error naming the
  // option at fault (--world-size, --rank, --master) or, after the timeout, saying which
  // ranks never came.
  explicit DistributedGroup(const DistributedOptions& options);
  ~DistributedGroup();
  DistributedGroup(const DistributedGroup&) = delete;
  DistributedGroup& operator=(const DistributedGroup&) = delete;

  int rank() const { return options_.rank; }
  int world_size() const { return options_.world_size; }
  bool is_root() const { return options_.rank == 0; }
  double timeout_seconds() const { return options_.timeout_seconds; }

  // Every rank gets the element-wise sum over ranks, in place. t: any shape, float32,
  // float64 or int64, on any device (staged through host memory when not on the CPU).
  // A peer that died or stays silent past the timeout is a pb4u::Error, never a hang.
  void all_reduce_sum(torch::Tensor& t);
  // Averages the tensors over ranks in place, through one flat float64 buffer (one
  // collective instead of one per tensor). Undefined tensors are skipped.
  void all_reduce_mean(std::vector<torch::Tensor>& tensors);
  // Every rank gets `root`'s values of t, in place (same shape and dtype on every rank).
  void broadcast(torch::Tensor& t, int root = 0);
  // Every rank gets `root`'s string (sizes may differ between ranks before the call).
  std::string broadcast_bytes(const std::string& bytes, int root = 0);
  void barrier();

 private:
  struct Impl;
  DistributedOptions options_;
  std::unique_ptr<Impl> impl_;  // null for a group of one
};

// False when this pb4u was built without Gloo's headers (then only groups of one exist).
bool distributed_available();

// "HOST:PORT" -> (host, port); pb4u::Error naming `option` on anything else.
std::pair<std::string, int> parse_host_port(const std::string& text, const std::string& option);

}  // namespace pb4u
