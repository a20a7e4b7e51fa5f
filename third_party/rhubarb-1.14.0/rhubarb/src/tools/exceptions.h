#pragma once

#include <string>

std::string getMessage(const std::exception& e);