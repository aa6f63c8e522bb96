// The backend registry (render/registry.cpp, render/backend.h): a backend registered in one place is named
// wherever backends are: the --help of every command that takes --backend (built by the CLI's own
// subcommand functions), the error for an unknown name, and stress's list; when its handle goes, it is gone.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "render/backend.h"
#include "stress/backends.h"
#include "test_support.h"

namespace aovar::test {
namespace {

constexpr const char* kRegistryFakeName = "fakeapi";
constexpr const char* kRegistryFakeWhy = "fakeapi: no such driver here";

// Enough of a backend to be told apart from the built-in ones; rendering is not its test.
class RegistryFakeBackend final : public render::Backend {
 public:
  RegistryFakeBackend() { info_.backend = kRegistryFakeName; }
  const render::DeviceInfo& info() const override { return info_; }
  render::ClipDepth clip_depth() const override { return render::ClipDepth::zero_to_one; }
  void set_scene(const scene::Scene&) override {}
  std::unique_ptr<render::PreparedPipeline> prepare(const render::PipelinePlan&, render::Extent) override {
    throw render::BackendError("fakeapi: prepares nothing");
  }
  std::vector<double> render(render::PreparedPipeline&, const render::FrameSetup&) override { return {}; }
  image::FloatImage read_result(render::PreparedPipeline&) override { return {}; }
  void set_params(render::PreparedPipeline&, std::size_t, const std::vector<float>&) override {}

 private:
  render::DeviceInfo info_;
};

render::BackendRegistration register_fake() {
  return render::register_backend({kRegistryFakeName, variants::Target::gles30,
                                   [](const render::BackendOptions&) { return std::make_unique<RegistryFakeBackend>(); },
                                   [] { return std::string(kRegistryFakeWhy); }});
}

// The --help of each subcommand that takes --backend, as `aovar <command> --help` prints it.
std::vector<std::pair<std::string, std::string>> backend_command_helps() {
  const std::vector<std::function<cli::Command(CLI::App&)>> adders = {cli::add_measure, cli::add_sweep, cli::add_ship,
                                                                      cli::add_stress, cli::add_calibrate};
  std::vector<std::pair<std::string, std::string>> helps;
  for (const auto& add : adders) {
    CLI::App app;
    const cli::Command c = add(app);
    helps.emplace_back(c.app->get_name(), c.app->help());
  }
  return helps;
}

std::string error_text(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

TEST(BackendRegistry, FakeBackendShowsInEveryBackendCommandsHelp) {
  for (const auto& [name, help] : backend_command_helps())
    EXPECT_FALSE(has_text(help, kRegistryFakeName)) << name << " before registering:\n" << help;
  {
    const auto fake = register_fake();
    for (const auto& [name, help] : backend_command_helps()) {
      EXPECT_TRUE(has_text(help, kRegistryFakeName)) << name << ":\n" << help;
      EXPECT_TRUE(has_text(help, render::default_backend())) << name << ":\n" << help;
    }
  }
  for (const auto& [name, help] : backend_command_helps())
    EXPECT_FALSE(has_text(help, kRegistryFakeName)) << name << " after the handle went:\n" << help;
}

TEST(BackendRegistry, UnknownNameErrorListsTheFakeBackend) {
  const auto fake = register_fake();
  for (const std::string& what : {error_text([] { render::make_backend("metal", {}); }),
                                  error_text([] { render::target_of("metal"); })}) {
    EXPECT_TRUE(has_text(what, "unknown backend 'metal'")) << what;
    EXPECT_TRUE(has_text(what, "gles or fakeapi)")) << what;
    EXPECT_TRUE(is_one_line(what)) << what;
  }
}

TEST(BackendRegistry, StressTakesTheFakeBackendAndListsIt) {
  const auto fake = register_fake();
  EXPECT_EQ(stress::targets_of({kRegistryFakeName}), std::vector<variants::Target>{variants::Target::gles30});
  EXPECT_EQ(stress::targets_of({render::default_backend(), kRegistryFakeName, "gles"}),
            (std::vector<variants::Target>{render::target_of(render::default_backend()), variants::Target::gles30}));
  const std::string what = error_text([] { stress::targets_of({"metal"}); });
  EXPECT_TRUE(has_text(what, "stress: unknown backend 'metal'")) << what;
  EXPECT_TRUE(has_text(what, ", fakeapi)")) << what;
}

TEST(BackendRegistry, FakeBackendIsMadeThroughItsEntryUntilTheHandleGoes) {
  {
    const auto fake = register_fake();
    EXPECT_EQ(render::make_backend(kRegistryFakeName, {})->info().backend, kRegistryFakeName);
    EXPECT_EQ(render::target_of(kRegistryFakeName), variants::Target::gles30);
    EXPECT_EQ(render::backend_info(kRegistryFakeName).unavailable(), kRegistryFakeWhy);
    EXPECT_EQ(render::backend_names().back(), kRegistryFakeName);
    EXPECT_THROW((void)register_fake(), render::BackendError);  // one entry per name
  }
  EXPECT_TRUE(has_text(error_text([] { render::make_backend(kRegistryFakeName, {}); }), "unknown backend 'fakeapi'"));
}

TEST(BackendRegistry, BuiltInBackendsComeFirstWithTheDefaultAtTheHead) {
  const auto fake = register_fake();
  const auto builtin = render::builtin_backends();
  const auto names = render::backend_names();
  ASSERT_EQ(names.size(), builtin.size() + 1);
  for (std::size_t i = 0; i < builtin.size(); ++i) EXPECT_EQ(names[i], builtin[i].name);
  EXPECT_EQ(render::default_backend(), names.front());
  // The first backend of each target names it in errors ("fetch traces run on ... only").
  EXPECT_EQ(render::backend_for(variants::Target::gles30), "gles");
  EXPECT_EQ(render::target_of(render::backend_for(variants::Target::vulkan)), variants::Target::vulkan);
}

// The suite renders on every built-in backend, so each must say it can start here.
TEST(BackendRegistry, BuiltInBackendsAreAvailableHere) {
  for (const auto& b : render::builtin_backends()) EXPECT_EQ(b.unavailable(), "") << b.name;
}

}  // namespace
}  // namespace aovar::test
