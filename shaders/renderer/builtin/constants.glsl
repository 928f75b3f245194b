// Orbis built-in GLSL constants. Prepended to every stage of a program built with
// ShaderProgramDescription::builtinLibrary (the default). Names start with og_.
const float og_pi = 3.14159265358979323846;
const float og_oneOverPi = 0.318309886183790671538;
const float og_halfPi = 1.57079632679489661923;
const float og_twoPi = 6.28318530717958647692;
const float og_oneOverTwoPi = 0.159154943091895335769;
const float og_radiansPerDegree = 0.0174532925199432957692;
const float og_degreesPerRadian = 57.2957795130823208768;
const float og_maximumFloat = 3.402823466e+38;
