#pragma once

#include "AudioClip.h"

void createWaveFile(const AudioClip& audioClip, std::string fileName);
