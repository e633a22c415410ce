// --set overrides: "path=value" assignments applied to a scene's raw JSON before validation.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace imx::scene_json {

// Applies one assignment. The path is dotted keys with array indices as numbers or in brackets
// ("objects.0.material.opacity", "objects[0].material.opacity"); an array of objects may also be
// indexed by an element's "name" ("objects.implant.material.opacity"). Missing object keys are
// created. The value is JSON when it parses as JSON, else a string.
// Throws imx::Error "origin: EDIT: problem", EDIT being `edit` when given (the Python binding's
// "scene.set('path')"), else "--set ASSIGNMENT" as the CLI takes it.
void apply_override(nlohmann::json& root, const std::string& assignment, const std::string& origin,
                    const std::string& edit = "");

}  // namespace imx::scene_json
