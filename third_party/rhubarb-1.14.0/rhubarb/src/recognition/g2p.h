#pragma once

#include <vector>
#include "core/Phone.h"

std::vector<Phone> wordToPhones(const std::string& word);
