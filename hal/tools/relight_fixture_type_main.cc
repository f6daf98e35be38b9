// relight-fixture-type: a DMX fixture type (a QLC+ .qxf or relight's .toml)
// printed in the TOML form, e.g. to copy a library type and add what it lacks
// (a zoom range, a colour wheel's colours) before patching it (docs/dmx.md
// "Adding a fixture type"). The output is read back before it is written:
// a type that would not read back the same is an error, not a file.
//
//   relight-fixture-type Martin/Martin-MAC-Aura.qxf -o fixtures/dmx/mac-aura.toml
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <CLI/CLI.hpp>

#include "relight/hal/dmx/fixture_type.h"

namespace {

using namespace relight::hal;

// As given, else relative to QLC+'s library (as the DMX patch resolves types).
std::string Resolve(const std::string& path) {
  const std::string in_library = std::string(kQlcFixtureDir) + "/" + path;
  if (!std::filesystem::exists(path) && !path.empty() && path[0] != '/' && std::filesystem::exists(in_library)) {
    return in_library;
  }
  return path;
}

int Convert(const std::string& path, const std::string& out_path) {
  FixtureType type;
  const relight::Status loaded = LoadFixtureType(Resolve(path), &type);
  if (!loaded.ok()) {
    std::fprintf(stderr, "relight-fixture-type: %s\n", loaded.message().c_str());
    return 1;
  }
  const std::string toml = FixtureTypeToToml(type);
  FixtureType back;
  const relight::Status reread = ParseFixtureTypeToml(toml, "(written form)", &back);
  const std::string difference = reread.ok() ? FixtureTypeDifference(type, back) : reread.message();
  if (!difference.empty()) {
    std::fprintf(stderr, "relight-fixture-type: %s: the TOML form would not read back the same: %s\n",
                 type.where.c_str(), difference.c_str());
    return 1;
  }
  if (out_path.empty()) {
    std::fwrite(toml.data(), 1, toml.size(), stdout);
    return 0;
  }
  std::ofstream out(out_path, std::ios::binary);
  out << toml;
  out.close();
  if (!out) {
    std::fprintf(stderr, "relight-fixture-type: %s: cannot write\n", out_path.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "relight-fixture-type: print a DMX fixture type in relight's TOML form.\n"
      "Reads a QLC+ fixture definition (.qxf) or a relight .toml type and writes the\n"
      "TOML form, which you can edit and patch like any type (docs/dmx.md, \"Adding a\n"
      "fixture type\"): e.g. copy a library type to add a zoom range (beam_deg) or the\n"
      "colours of a wheel it lacks. Only what relight renders is kept: channels it\n"
      "ignores (gobos, prisms, macros) stay as \"ignored\" so DMX offsets are right."};
  app.footer(
      "Example:\n"
      "  relight-fixture-type Martin/Martin-MAC-Aura.qxf -o fixtures/dmx/mac-aura.toml\n"
      "A relative path not found as given is looked up in " + std::string(kQlcFixtureDir) + ".");
  std::string path, out_path;
  app.add_option("type", path, ".qxf or .toml fixture type")->required();
  app.add_option("-o,--output", out_path, "write the TOML form to this file (default: standard output)");
  CLI11_PARSE(app, argc, argv);
  return Convert(path, out_path);
}
