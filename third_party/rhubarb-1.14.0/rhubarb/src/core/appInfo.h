#pragma once

#include <string>

extern const std::string appName;
extern const std::string appVersion;
