// libFuzzer target: the UFF 58/58b reader, in full and headers only, and what callers do with
// what it returns (select a dataset, convert it to a receptance, write it and read it back).
// parse_uff may not throw at all; selection and conversion only InputError; nothing read may
// exceed what the bytes can hold, and what is written must read back alike. A broken rule aborts
// (a libFuzzer crash), as does any AddressSanitizer or UndefinedBehaviorSanitizer finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz_util.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/uff.hpp"

using namespace toolpoint;
using fuzz::require;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const UffFile full = parse_uff(bytes, "fuzz.uff");
  const UffFile headers = parse_uff(bytes, "fuzz.uff", {.headers_only = true});
  require(headers.datasets.size() == full.datasets.size());
  for (const UffDataset58& d : headers.functions) require(d.x.empty() && d.y.empty() && d.headers_only);
  for (const UffDataset58& d : full.functions) {
    require(d.x.size() == d.y.size());
    require(static_cast<long long>(d.size()) <= d.declared_points);
    require(d.size() <= size / 2 + 1);
    for (std::optional<FrfOrdinate> o : {std::optional<FrfOrdinate>(), std::optional(FrfOrdinate::Accelerance)}) {
      try {
        const UffReceptance r = uff_receptance(d, o, "fuzz.uff");
        require(r.receptance.frequency_hz.size() == r.receptance.values.size());
      } catch (const InputError&) {}
    }
  }
  try {
    select_dataset58(full, {});
  } catch (const InputError&) {}
  std::vector<UffDataset58> writable;
  for (const UffDataset58& d : full.functions) {
    try {
      d.check();
      writable.push_back(d);
    } catch (const InvalidArgument&) {}
  }
  if (!writable.empty()) {
    for (bool binary : {false, true}) {
      const UffFile again = parse_uff(format_uff(writable, {.binary = binary}).bytes, "again.uff");
      require(again.functions.size() == writable.size());
      for (std::size_t k = 0; k < writable.size(); ++k) {
        require(again.functions[k].size() == writable[k].size());
        if (binary && writable[k].is_double())
          for (std::size_t i = 0; i < writable[k].size(); ++i)
            require(again.functions[k].y[i] == writable[k].y[i] || writable[k].y[i] != writable[k].y[i]);
      }
    }
  }
  return 0;
}
