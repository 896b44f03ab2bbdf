#pragma once
// Deletes a file or a directory with everything under it, like std::filesystem::remove_all,
// which pb4u must not call: PyTorch's wheels (2.x) export their own statically linked copy of
// it from libtorch, the dynamic linker binds a program's call to that copy ahead of libstdc++'s,
// and it crashes (calls address 0) on a non-empty directory (pytorch/pytorch#133437). This one
// walks the tree with POSIX nftw and needs no libstdc++ filesystem symbol.
#include <cstdint>
#include <string>

namespace pb4u {

// Removes `path` and, for a directory, all it holds, depth first; a symbolic link is removed,
// never followed. Returns how many entries were removed (0 if `path` does not exist). Throws
// pb4u::Error naming the entry that could not be removed.
std::uintmax_t remove_tree(const std::string& path);

}  // namespace pb4u
