#pragma once

#include <filesystem>

std::string readUtf8File(std::filesystem::path filePath);