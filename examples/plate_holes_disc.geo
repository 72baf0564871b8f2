// The CLI fixture of issue 20: a 40 x 30 x 2 mm plate with two 3 mm-radius through holes and a 6 mm-radius,
// 0.5 mm thick piezo disc bonded on top, in metres (modalfe reads .geo files in metres). OpenCASCADE kernel;
// BooleanFragments makes the disc and the plate share their common face (a conforming mesh), which is the
// ground electrode; the disc's top is the driven one, the plate's x = 0 end the clamp.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.04, 0.03, 0.002};
Cylinder(2) = {0.01, 0.015, 0, 0, 0, 0.002, 0.003};
Cylinder(3) = {0.03, 0.015, 0, 0, 0, 0.002, 0.003};
BooleanDifference(4) = { Volume{1}; Delete; }{ Volume{2, 3}; Delete; };
Cylinder(5) = {0.02, 0.015, 0.002, 0, 0, 0.0005, 0.006};
BooleanFragments{ Volume{4, 5}; Delete; }{}
eps = 1e-6;
Physical Volume("plate") = {4};
Physical Volume("disc") = {5};
Physical Surface("clamp") = Surface In BoundingBox{-eps, -eps, -eps, eps, 0.03 + eps, 0.002 + eps};
Physical Surface("electrode_top") = Surface In BoundingBox{0.014 - eps, 0.009 - eps, 0.0025 - eps, 0.026 + eps, 0.021 + eps, 0.0025 + eps};
Physical Surface("electrode_bottom") = Surface In BoundingBox{0.014 - eps, 0.009 - eps, 0.002 - eps, 0.026 + eps, 0.021 + eps, 0.002 + eps};
