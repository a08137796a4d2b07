// libFuzzer target, the CLI's YAML reader (src/cli/yaml_request.cpp): bytes as a YAML document
// -> requestFromYaml and sphereRequestFromYaml. Expected: a request, a YAML::Exception (syntax,
// conversions) or an InterpolationError naming the field; anything else is a finding. The seed
// corpus is the CLI's test requests (test/cli/data/*.yaml).
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "../../src/cli/yaml_request.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  YAML::Node root;
  try
  {
    root = YAML::Load(text);
  }
  catch (const YAML::Exception&)
  {
    return 0;  // not YAML: the CLI reports it with exit status 2
  }
  // One parse for both readers (parsing dominates the cost of an input).
  for (int space = 0; space < 2; ++space)
  {
    try
    {
      if (space == 0)
        se3_interpolation::cli::requestFromYaml(root);
      else
        se3_interpolation::cli::sphereRequestFromYaml(root);
    }
    catch (const YAML::Exception&)
    {
      // Not YAML, or a value of the wrong type: the CLI reports it with exit status 2.
    }
    catch (const se3_interpolation::InterpolationError&)
    {
      // A field-naming error, as expected.
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "fuzz_yaml: an unexpected exception escaped: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
