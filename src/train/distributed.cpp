#include "pb4u/train/distributed.h"

#ifndef PB4U_NO_GLOO
// ProcessGroupGloo.hpp is empty unless the including code says that torch was built with
// Gloo (Debian's and the PyTorch wheels' libtorch are; the declarations are all it needs).
#ifndef USE_C10D_GLOO
#define USE_C10D_GLOO 1
#endif
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>
#endif

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <sstream>

#include "pb4u/util/error.h"

namespace pb4u {

#ifndef PB4U_NO_GLOO
namespace {

// c10 and gloo messages span lines (and backtraces); the CLI prints one line.
std::string first_line(const std::exception& e) {
  const auto* c10_error = dynamic_cast<const c10::Error*>(&e);
  std::string text = c10_error ? c10_error->what_without_backtrace() : e.what();
  text = text.substr(0, text.find('\n'));
  return text.size() > 240 ? text.substr(0, 240) + "..." : text;
}

bool is_loopback(const std::string& host) {
  return host == "localhost" || host.rfind("127.", 0) == 0 || host == "::1";
}

// The network interface Gloo binds to. GLOO_SOCKET_IFNAME wins (as in PyTorch); a loopback
// master means a single-machine group; otherwise this machine's hostname address.
std::shared_ptr<::gloo::transport::Device> gloo_device(const std::string& master_host) {
  if (const char* iface = std::getenv("GLOO_SOCKET_IFNAME"); iface && *iface)
    return c10d::ProcessGroupGloo::createDeviceForInterface(iface);
  if (is_loopback(master_host)) return c10d::ProcessGroupGloo::createDeviceForHostname("127.0.0.1");
  return c10d::ProcessGroupGloo::createDefaultDevice();
}

}  // namespace
#endif

std::pair<std::string, int> parse_host_port(const std::string& text, const std::string& option) {
  const size_t colon = text.rfind(':');
  auto fail = [&] { throw Error(option + ": expected HOST:PORT (e.g. 127.0.0.1:29500), got '" + text + "'"); };
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) fail();
  const std::string port_text = text.substr(colon + 1);
  if (port_text.find_first_not_of("0123456789") != std::string::npos || port_text.size() > 5) fail();
  const int port = std::stoi(port_text);
  if (port < 1 || port > 65535) fail();
  return {text.substr(0, colon), port};
}

namespace {

// "1.5 s", "300 s".
std::string seconds_text(double seconds) {
  std::ostringstream s;
  s << seconds << " s";
  return s.str();
}

// The options' one-line errors, before any socket is opened; returns the master's host, port.
std::pair<std::string, int> check_options(const DistributedOptions& o) {
  if (o.world_size < 1) throw Error("--world-size: must be at least 1, got " + std::to_string(o.world_size));
  if (o.rank < 0 || o.rank >= o.world_size)
    throw Error("--rank: must be in 0.." + std::to_string(o.world_size - 1) + ", got " + std::to_string(o.rank));
  if (!(o.timeout_seconds > 0)) throw Error("--timeout: must be positive, got " + seconds_text(o.timeout_seconds));
  return parse_host_port(o.master, "--master");
}

}  // namespace

#ifdef PB4U_NO_GLOO
bool distributed_available() { return false; }

struct DistributedGroup::Impl {};

DistributedGroup::DistributedGroup(const DistributedOptions& options) : options_(options) {
  check_options(options_);
  if (options_.world_size != 1)
    throw Error("--world-size: this pb4u was built without Gloo (libgloo-dev), so it trains in one process only");
}
DistributedGroup::~DistributedGroup() = default;
void DistributedGroup::all_reduce_sum(torch::Tensor&) {}
void DistributedGroup::all_reduce_mean(std::vector<torch::Tensor>&) {}
void DistributedGroup::broadcast(torch::Tensor&, int) {}
std::string DistributedGroup::broadcast_bytes(const std::string& bytes, int) { return bytes; }
void DistributedGroup::barrier() {}
#else
bool distributed_available() { return true; }

struct DistributedGroup::Impl {
  c10::intrusive_ptr<c10d::Store> store;
  c10::intrusive_ptr<c10d::ProcessGroupGloo> group;
  std::string where;  // "rank R of N" for messages

  // Runs one collective; a failure (peer gone, timeout) becomes a one-line pb4u::Error.
  void run(const char* what, const std::function<c10::intrusive_ptr<c10d::Work>()>& start,
           double timeout_seconds) {
    try {
      start()->wait();
    } catch (const std::exception& e) {
      throw Error("distributed " + std::string(what) + " failed on " + where +
                  ": another rank died or did not answer within " + seconds_text(timeout_seconds) + " (" +
                  first_line(e) + ")");
    }
  }
};

DistributedGroup::DistributedGroup(const DistributedOptions& options) : options_(options) {
  const auto [host, port] = check_options(options_);
  if (options_.world_size == 1) return;
  // A write to a dead peer's socket raises SIGPIPE, whose default action ends this rank before
  // the collective can report the failure (the kill-one-rank test saw it now and then). Ignored,
  // the write fails with EPIPE and the rank exits with its one-line error; Python, and so
  // PyTorch's own launchers, ignore it from start-up.
  std::signal(SIGPIPE, SIG_IGN);

  impl_ = std::make_unique<Impl>();
  impl_->where = "rank " + std::to_string(options_.rank) + " of " + std::to_string(options_.world_size);
  const auto timeout = std::chrono::milliseconds(static_cast<int64_t>(options_.timeout_seconds * 1000));
  try {
    c10d::TCPStoreOptions store_options;
    store_options.port = static_cast<std::uint16_t>(port);
    store_options.isServer = options_.rank == 0;
    store_options.numWorkers = static_cast<std::size_t>(options_.world_size);
    store_options.waitWorkers = true;
    store_options.timeout = timeout;
    impl_->store = c10::make_intrusive<c10d::TCPStore>(host, store_options);
    auto gloo_options = c10d::ProcessGroupGloo::Options::create(timeout);
    gloo_options->devices.push_back(gloo_device(host));
    impl_->group = c10::make_intrusive<c10d::ProcessGroupGloo>(impl_->store, options_.rank,
                                                               options_.world_size, gloo_options);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("--master " + options_.master + ": " + impl_->where + " could not join a group of " +
                std::to_string(options_.world_size) + " ranks within " + seconds_text(options_.timeout_seconds) +
                " (" + first_line(e) + ")");
  }
}

DistributedGroup::~DistributedGroup() = default;

void DistributedGroup::all_reduce_sum(torch::Tensor& t) {
  if (!impl_ || !t.defined()) return;
  torch::Tensor host = t.is_cpu() && t.is_contiguous() ? t : t.to(torch::kCPU).contiguous();
  std::vector<at::Tensor> tensors{host};
  impl_->run("all-reduce", [&] { return impl_->group->allreduce(tensors); }, options_.timeout_seconds);
  if (!host.is_same(t)) {
    torch::NoGradGuard no_grad;
    t.copy_(host);
  }
}

void DistributedGroup::all_reduce_mean(std::vector<torch::Tensor>& tensors) {
  if (!impl_) return;
  std::vector<torch::Tensor> flat;
  for (const auto& t : tensors)
    if (t.defined()) flat.push_back(t.detach().to(torch::kCPU, torch::kFloat64).reshape({-1}));
  if (flat.empty()) return;
  torch::Tensor buffer = torch::cat(flat);
  all_reduce_sum(buffer);
  buffer.div_(static_cast<double>(options_.world_size));
  int64_t offset = 0;
  torch::NoGradGuard no_grad;
  for (auto& t : tensors) {
    if (!t.defined()) continue;
    t.copy_(buffer.narrow(0, offset, t.numel()).view(t.sizes()));
    offset += t.numel();
  }
}

void DistributedGroup::broadcast(torch::Tensor& t, int root) {
  if (!impl_ || !t.defined()) return;
  torch::Tensor host = t.is_cpu() && t.is_contiguous() ? t : t.to(torch::kCPU).contiguous();
  std::vector<at::Tensor> tensors{host};
  c10d::BroadcastOptions opts;
  opts.rootRank = root;
  impl_->run("broadcast", [&] { return impl_->group->broadcast(tensors, opts); }, options_.timeout_seconds);
  if (!host.is_same(t)) {
    torch::NoGradGuard no_grad;
    t.copy_(host);
  }
}

std::string DistributedGroup::broadcast_bytes(const std::string& bytes, int root) {
  if (!impl_) return bytes;
  torch::Tensor size = torch::tensor({static_cast<int64_t>(bytes.size())}, torch::kInt64);
  broadcast(size, root);
  torch::Tensor data = torch::zeros({size.item<int64_t>()}, torch::kUInt8);
  if (rank() == root && !bytes.empty()) std::memcpy(data.data_ptr(), bytes.data(), bytes.size());
  if (data.numel() > 0) broadcast(data, root);
  return std::string(reinterpret_cast<const char*>(data.data_ptr()), static_cast<size_t>(data.numel()));
}

void DistributedGroup::barrier() {
  if (!impl_) return;
  // An all-reduce of one number: Gloo's barrier has no timeout of its own in every version.
  torch::Tensor one = torch::ones({1}, torch::kInt64);
  all_reduce_sum(one);
}

#endif  // PB4U_NO_GLOO

}  // namespace pb4u
