// The config path: defaults, overrides, and errors that name the file, line and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <set>
#include <fstream>

#include "app/run_config.h"
#include "config/param.h"
#include "util/error.h"

namespace rtusim {
namespace {

std::string write_config(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "rtusim_config_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

std::string error_of(const std::string& path, const std::vector<std::string>& overrides = {}) {
  try {
    load_run_config(path, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsAndEffectiveConfig) {
  const auto path = write_config("empty.toml", "");
  const RunConfig c = load_run_config(path, {});
  EXPECT_EQ(c.scene.resolved, "builtin:cornell");
  EXPECT_EQ(c.image.width, 256);
  EXPECT_EQ(c.tracer.max_depth, 4);
  EXPECT_EQ(c.layout.kinds, std::vector<std::string>{"dfl"});
  // The effective config holds every key with its value, defaults included.
  EXPECT_EQ(c.effective["tracer"]["max_depth"].value<int64_t>(), 4);
  EXPECT_EQ(c.effective["tracer"]["ray_order"].value<std::string>(), "recursive");
  EXPECT_EQ(c.effective["kdtree"]["isect_cost"].value<double>(), 80.0);
}

TEST(Config, OverridesWinAndParseTomlValues) {
  const auto path = write_config("o.toml", "[image]\nwidth = 64\n");
  const RunConfig c = load_run_config(
      path, {"image.width=32", "tracer.ray_order=wavefront", "camera.eye=[0, 1, 2]",
             "camera.target=[0,0,0]", "tracer.ambient=0.25"});
  EXPECT_EQ(c.image.width, 32);
  EXPECT_EQ(c.tracer.order, RayOrder::kWavefront);
  ASSERT_TRUE(c.camera.has_value());
  EXPECT_EQ(c.camera->eye, glm::vec3(0, 1, 2));
  EXPECT_FLOAT_EQ(c.tracer.ambient, 0.25f);
}

TEST(Config, UnknownKeyNamesFileLineAndKey) {
  const auto path = write_config("unknown.toml", "[image]\nwidth = 64\n\n[l1]\nsizee = 8192\n");
  const std::string e = error_of(path);
  EXPECT_NE(e.find("unknown.toml:5"), std::string::npos) << e;
  EXPECT_NE(e.find("l1.sizee"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Config, WrongTypeAndRange) {
  const auto p1 = write_config("type.toml", "[image]\nwidth = \"wide\"\n");
  const std::string e1 = error_of(p1);
  EXPECT_NE(e1.find("type.toml:2"), std::string::npos) << e1;
  EXPECT_NE(e1.find("image.width"), std::string::npos) << e1;
  EXPECT_NE(e1.find("expected an integer"), std::string::npos) << e1;

  const auto p2 = write_config("range.toml", "[tracer]\n\nmax_depth = 99\n");
  const std::string e2 = error_of(p2);
  EXPECT_NE(e2.find("range.toml:3"), std::string::npos) << e2;
  EXPECT_NE(e2.find("between 0 and 16"), std::string::npos) << e2;

  const auto p3 = write_config("enum.toml", "[layout]\nkind = \"bfs\"\n");
  const std::string e3 = error_of(p3);
  EXPECT_NE(e3.find("layout.kind"), std::string::npos) << e3;
  EXPECT_NE(e3.find("'bfs'"), std::string::npos) << e3;
}

TEST(Config, OverrideErrorsNameTheOption) {
  const auto path = write_config("ok.toml", "");
  const std::string e = error_of(path, {"image.height=-3"});
  EXPECT_NE(e.find("--set image.height=-3"), std::string::npos) << e;
  EXPECT_NE(error_of(path, {"nonsense"}).find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error_of(path, {"image.depth=3"}).find("unknown key"), std::string::npos);
}

TEST(Config, SyntaxErrorAndMissingFile) {
  const auto path = write_config("syntax.toml", "[image]\nwidth = = 3\n");
  const std::string e = error_of(path);
  EXPECT_NE(e.find("syntax.toml:2"), std::string::npos) << e;
  EXPECT_NE(error_of("/nonexistent/x.toml").find("/nonexistent/x.toml: config file not found"),
            std::string::npos);
}

TEST(Config, ScenePathsResolve) {
  EXPECT_EQ(resolve_scene_path("builtin:cornell", "/x"), "builtin:cornell");
  EXPECT_EQ(resolve_scene_path("a/b.gltf", "/cfg"), "/cfg/a/b.gltf");
  EXPECT_EQ(resolve_scene_path("/abs/b.gltf", "/cfg"), "/abs/b.gltf");
  setenv("RTUSIM_SCENES", "/my/scenes", 1);
  EXPECT_EQ(resolve_scene_path("$RTUSIM_SCENES/box/box.gltf", "/cfg"), "/my/scenes/box/box.gltf");
  unsetenv("RTUSIM_SCENES");
}

TEST(Config, CameraNeedsEyeAndTarget) {
  const auto path = write_config("cam.toml", "[camera]\neye = [0, 0, 1]\n");
  EXPECT_NE(error_of(path).find("camera.target"), std::string::npos);
}

TEST(Config, SetErrorsNameTheSet) {
  // A value from --set is reported against the --set, also when a check across keys fails.
  const auto path = write_config("set.toml", "[l1]\nsize = 8192\n");
  EXPECT_EQ(error_of(path, {"l1.assoc=256"}),
            "--set l1.assoc=256: l1.size: 8192 is smaller than l1.line x l1.assoc (16384)");
  EXPECT_EQ(error_of(path, {"dram.channels=0"}).rfind("--set dram.channels=0: dram.channels:", 0),
            0u)
      << error_of(path, {"dram.channels=0"});
  // Without a --set, the file and the line of the key it sets.
  const auto bad = write_config("bad.toml", "[image]\nwidth = 8\n[dram]\nrow_bytes = 100\n");
  EXPECT_EQ(error_of(bad), bad + ":4: dram.bus_bytes: 8 x dram.burst_length 8 = 64 bytes per burst does not divide "
                "dram.row_bytes = 100");
}

TEST(Config, EveryDeclaredKeyIsReadAndEveryReadKeyDeclared) {
  // With an explicit camera and background (keys without a default are recorded only when
  // given) every key is read; the effective config then holds exactly the declared keys.
  const auto path = write_config("all.toml",
                                 "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\nup = [0, 1, 0]\n"
                                 "[tracer]\nbackground = [0, 0, 0]\n");
  const RunConfig c = load_run_config(path, {});
  std::set<std::string> effective, declared;
  std::function<void(const toml::table&, const std::string&)> walk =
      [&](const toml::table& t, const std::string& prefix) {
        for (const auto& [k, v] : t) {
          const std::string name = prefix + std::string(k.str());
          if (const auto* sub = v.as_table()) walk(*sub, name + ".");
          else effective.insert(name);
        }
      };
  walk(c.effective, "");
  for (const ParamDecl* d : declared_params()) {
    EXPECT_TRUE(declared.insert(d->key()).second) << d->key() << " declared twice";
  }
  EXPECT_EQ(effective, declared);
  EXPECT_GE(declared.size(), 50u);
}

}  // namespace
}  // namespace rtusim
