// A main for the fuzz targets when they are built without libFuzzer (gcc, the CI smoke):
// runs every input file given (files or directories), then --runs inputs made by mutating
// them (byte flips, inserted and deleted ranges, interesting values, splices of two inputs)
// from a fixed --seed, so a smoke run is the same on every machine. The real fuzzing is
// `scripts/fuzz` (clang, libFuzzer, sanitizers); this only keeps the targets honest in CI.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) __attribute__((weak));

namespace {

using Bytes = std::vector<uint8_t>;

void AddFile(const std::filesystem::path& path, std::vector<Bytes>* inputs) {
  std::ifstream in(path, std::ios::binary);
  inputs->emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

Bytes Mutate(const std::vector<Bytes>& inputs, std::mt19937_64& rng) {
  auto pick = [&](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  Bytes b = inputs.empty() ? Bytes{} : inputs[pick(inputs.size())];
  const int steps = 1 + static_cast<int>(pick(8));
  static const uint8_t kInteresting[] = {0,   1,   0x7f, 0x80, 0xff, '@', ',',  '.',
                                         '-', 'e', '{',  '}',  ':',  '"', '\n', ' '};
  for (int s = 0; s < steps; ++s) {
    switch (pick(6)) {
      case 0:  // flip a bit
        if (!b.empty()) b[pick(b.size())] ^= static_cast<uint8_t>(1u << pick(8));
        break;
      case 1:  // an interesting byte
        if (!b.empty()) b[pick(b.size())] = kInteresting[pick(sizeof(kInteresting))];
        break;
      case 2: {  // insert random bytes
        const size_t at = pick(b.size() + 1), n = 1 + pick(16);
        Bytes r(n);
        for (auto& x : r) x = static_cast<uint8_t>(rng());
        b.insert(b.begin() + static_cast<long>(at), r.begin(), r.end());
        break;
      }
      case 3: {  // delete a range
        if (b.empty()) break;
        const size_t at = pick(b.size()), n = 1 + pick(std::min<size_t>(32, b.size() - at));
        b.erase(b.begin() + static_cast<long>(at), b.begin() + static_cast<long>(at + n));
        break;
      }
      case 4: {  // duplicate a range
        if (b.empty() || b.size() > (1u << 20)) break;
        const size_t at = pick(b.size()), n = 1 + pick(std::min<size_t>(64, b.size() - at));
        const Bytes chunk(b.begin() + static_cast<long>(at), b.begin() + static_cast<long>(at + n));
        b.insert(b.begin() + static_cast<long>(pick(b.size() + 1)), chunk.begin(), chunk.end());
        break;
      }
      default: {  // splice with another input
        if (inputs.empty()) break;
        const Bytes& o = inputs[pick(inputs.size())];
        const size_t keep = pick(b.size() + 1), from = pick(o.size() + 1);
        b.resize(keep);
        b.insert(b.end(), o.begin() + static_cast<long>(from), o.end());
        break;
      }
    }
  }
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  long runs = 1000;
  uint64_t seed = 1;
  std::vector<Bytes> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) {
      runs = std::atol(argv[++i]);
    } else if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--help" || a == "-h") {
      std::cout << "Usage: " << argv[0]
                << " [--runs N] [--seed S] INPUT_OR_DIR...\n"
                   "Runs each input, then N mutations of them (default 1000, seed 1). Built "
                   "without libFuzzer; scripts/fuzz builds the real fuzzer.\n";
      return 0;
    } else if (std::filesystem::is_directory(a)) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(a))
        if (e.is_regular_file()) AddFile(e.path(), &inputs);
    } else if (std::filesystem::is_regular_file(a)) {
      AddFile(a, &inputs);
    } else {
      std::cerr << argv[0] << ": no such input file or directory: " << a << "\n";
      return 2;
    }
  }
  for (const auto& in : inputs) LLVMFuzzerTestOneInput(in.data(), in.size());
  std::mt19937_64 rng(seed);
  for (long r = 0; r < runs; ++r) {
    const Bytes b = Mutate(inputs, rng);
    LLVMFuzzerTestOneInput(b.data(), b.size());
  }
  std::cout << argv[0] << ": " << inputs.size() << " inputs and " << runs
            << " mutations ran without a crash\n";
  return 0;
}
