#pragma once
// Case files: XML in, scene::Scene out. One schema table in src/io/case_xml.cpp (element,
// attribute, type, unit, default, bounds, description, where it lands in the Scene) drives the
// parser, the validation, `--set` overrides and describeCaseFormat(), so the four never drift.
// docs/case-format.md is the user-facing description of the format.
//
// Every problem in a case is a core::InputError whose message starts with "file:line: " (or
// "--set PATH=VALUE: " when an override caused it) and names the element, the attribute and what
// was expected, so a user can fix the case from the one line the CLI prints.
#include <string>
#include <vector>

#include "millsim/scene/scene.hpp"

namespace millsim::io {

// Reads and validates a case file. `overrides` are "path=value" strings ("time.end=2",
// "drum.lifters.count=4", "dem.damping=dualsphysics") applied to the document before validation;
// an element named by an override that the file lacks is created. Throws core::InputError.
scene::Scene loadCaseFile(const std::string& path, const std::vector<std::string>& overrides = {});

// Same as loadCaseFile for text already in memory; `source_name` is used in messages, as
// Scene::source and (its stem) as the default Scene::name.
scene::Scene loadCaseText(const std::string& xml, const std::string& source_name,
                          const std::vector<std::string>& overrides = {});

// The embedded default case, byte for byte the text of cases/ball_mill_300_balls.xml.
const char* defaultCaseXml();

// Markdown reference of the format: elements, then every attribute with type, unit, default,
// bounds and description, then the rules that involve more than one attribute.
std::string describeCaseFormat();

// Every attribute of the schema as the dotted path `--set` takes ("time.end",
// "drum.lifters.count", "name" for the root's attribute), in schema order.
std::vector<std::string> caseAttributePaths();

}  // namespace millsim::io
