#include "import_command.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "model.hpp"
#include "model_writer.hpp"
#ifdef MBRT_WITH_URDFDOM
#include "urdf_import.hpp"
#endif
#ifdef MBRT_WITH_MUJOCO
#include "mjcf_import.hpp"
#endif

namespace mbrt::codegen {

namespace {

constexpr const char* kImportUsage = "mbrt import ROBOT.urdf|MODEL.xml -o MODEL.yaml\n";

int usage_error(const std::string& message) {
  std::fprintf(stderr, "error: import: %s\nusage: %s", message.c_str(), kImportUsage);
  return 2;
}

[[maybe_unused]] int missing_library(const std::string& format, const std::string& package) {
  std::fprintf(stderr, "error: import: this mbrt was built without %s support: apt-get install %s, then rebuild mbrt\n",
               format.c_str(), package.c_str());
  return 2;
}

}  // namespace

int run_import(const std::string& source, const std::string& out) {
  const std::string extension = std::filesystem::path(source).extension().string();
  if (extension != ".urdf" && extension != ".xml") {
    return usage_error("'" + source + "': expected a URDF (.urdf) or MJCF (.xml) file");
  }
  if (!std::filesystem::is_regular_file(source)) throw std::runtime_error(source + ": no such file");
  ImportedModel model;
  if (extension == ".urdf") {
#ifdef MBRT_WITH_URDFDOM
    model = import_urdf(source);
#else
    return missing_library("URDF", "liburdfdom-dev");
#endif
  } else {
#ifdef MBRT_WITH_MUJOCO
    model = import_mjcf(source);
#else
    return missing_library("MJCF", "libmujoco-dev");
#endif
  }
  std::ofstream file(out);
  if (!(file << model_yaml(model) && file.flush())) return usage_error("-o: cannot write '" + out + "'");
  for (const std::string& w : model.warnings) std::fprintf(stderr, "warning: %s: %s\n", source.c_str(), w.c_str());
  try {
    load_model(out);  // what the importer wrote must be a valid model file
  } catch (const ModelError& e) {
    throw std::runtime_error(std::string(e.what()) + " (in the model imported from " + source + ")");
  }
  return 0;
}

}  // namespace mbrt::codegen
