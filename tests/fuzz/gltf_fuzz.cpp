// libFuzzer target: the glTF loader. An input starting with "glTF" is a .glb; otherwise it is
// a .gltf's JSON, optionally followed by a line "--bin--" and the bytes of its buffer file
// "fuzz.bin" (which the JSON may name as a buffer uri). Any InputError is a clean rejection.
#include <cstdint>
#include <cstring>
#include <string_view>

#include "fuzz_util.h"
#include "scene/gltf_loader.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rtusim;
  SceneLimits limits;
  limits.max_scene_bytes = uint64_t{64} << 20;  // keep each input's memory small
  std::filesystem::path path;
  if (size >= 4 && std::memcmp(data, "glTF", 4) == 0) {
    path = fuzz::write_file("fuzz.glb", data, size);
  } else {
    const std::string_view all(reinterpret_cast<const char*>(data), size);
    const size_t cut = all.find("\n--bin--\n");
    const size_t json_bytes = cut == std::string_view::npos ? size : cut;
    const size_t bin_at = cut == std::string_view::npos ? size : cut + 9;
    fuzz::write_file("fuzz.bin", data + bin_at, size - bin_at);
    path = fuzz::write_file("fuzz.gltf", data, json_bytes);
  }
  try {
    load_gltf(path.string(), limits);
  } catch (const InputError&) {
  }
  return 0;
}
