cmake_minimum_required(VERSION 3.24)

set(appName "Rhubarb Lip Sync")
set(appVersionMajor 1)
set(appVersionMinor 14)
set(appVersionPatch 0)
set(appVersionSuffix "")
set(appVersion "${appVersionMajor}.${appVersionMinor}.${appVersionPatch}${appVersionSuffix}")
