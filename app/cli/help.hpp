// The --help texts of contact2d and its verbs.
#pragma once

#include <string>

namespace c2d::app {

/// `contact2d --help`: the verbs, one or two lines each.
const char* main_help();

/// A verb's --help text; nullptr for an unknown verb.
const char* verb_help(const std::string& verb);

}  // namespace c2d::app
