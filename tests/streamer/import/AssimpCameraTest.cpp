// Cameras of files read through assimp (Collada here): placed by their node's world transform,
// vertical field of view from assimp's horizontal angle and the file's aspect ratio.
#include "ImportTestFiles.h"
#include "vastray/core/VecMath.h"

#include <algorithm>
#include <cmath>

namespace vastray::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One triangle and two perspective cameras: "Eye" inside a translated parent, turned 90 degrees
// about +Y, with yfov 40 and aspect 2; "Down" turned -90 degrees about +X, with xfov 50 and no
// aspect ratio (taken as square).
const std::string kCameraCollada = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_cameras>
    <camera id="wide-camera" name="wide"><optics><technique_common><perspective>
      <yfov>40</yfov><aspect_ratio>2</aspect_ratio><znear>0.1</znear><zfar>100</zfar>
    </perspective></technique_common></optics></camera>
    <camera id="down-camera" name="down"><optics><technique_common><perspective>
      <xfov>50</xfov><znear>0.1</znear><zfar>100</zfar>
    </perspective></technique_common></optics></camera>
  </library_cameras>
)" + std::string(kColladaTriangle) + R"(      <node id="rig" name="rig"><translate>0 0 10</translate>
        <node id="Eye" name="Eye"><translate>1 2 0</translate><rotate>0 1 0 90</rotate>
          <instance_camera url="#wide-camera"/></node>
      </node>
      <node id="Down" name="Down"><translate>0 5 0</translate><rotate>1 0 0 -90</rotate>
        <instance_camera url="#down-camera"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

Vec3f viewDirection(const Camera& c) { return normalize(c.target - c.eye); }

TEST(AssimpCameras, ColladaCamerasArePlacedByTheirNodesInWorldSpace) {
    auto r = importMesh(writeFile("cameras.dae", kCameraCollada));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.cameras.size(), 2u);
    const SceneCamera& eye = r->mesh.cameras[0];
    EXPECT_EQ(eye.name, "Eye");
    expectNear(eye.camera.eye, {1, 2, 10}, 1e-5f, "Eye: position (parent's translation + its own)");
    expectNear(viewDirection(eye.camera), {-1, 0, 0}, 1e-5f, "Eye: -Z turned 90 degrees about +Y");
    expectNear(eye.camera.up, {0, 1, 0}, 1e-5f, "Eye: up");
    EXPECT_NEAR(eye.camera.fovYDegrees, 40.0f, 1e-3f) << "the file's yfov, through assimp's horizontal angle";

    const SceneCamera& down = r->mesh.cameras[1];
    EXPECT_EQ(down.name, "Down");
    expectNear(down.camera.eye, {0, 5, 0}, 1e-5f, "Down: position");
    expectNear(viewDirection(down.camera), {0, -1, 0}, 1e-5f, "Down: looks down");
    expectNear(down.camera.up, {0, 0, -1}, 1e-5f, "Down: up turned with it");
    EXPECT_NEAR(down.camera.fovYDegrees, 50.0f, 1e-3f) << "no aspect ratio: square, vertical = horizontal";
    for (const std::string& warning : r->report.warnings)
        EXPECT_EQ(warning.find("cameras"), std::string::npos) << "no camera was dropped: " << warning;
}

// A camera whose node is scaled to nothing has no view direction: dropped with a warning,
// the other kept.
TEST(AssimpCameras, DegenerateCameraIsDroppedWithAWarning) {
    std::string text = kCameraCollada;
    const std::string rotate = "<rotate>1 0 0 -90</rotate>";
    text.replace(text.find(rotate), rotate.size(), "<scale>0 0 0</scale>");
    auto r = importMesh(writeFile("degenerate-camera.dae", text));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.cameras.size(), 1u);
    EXPECT_EQ(r->mesh.cameras[0].name, "Eye");
    bool warned = false;
    for (const std::string& warning : r->report.warnings) warned |= warning.find("1 cameras") != std::string::npos;
    EXPECT_TRUE(warned) << "expected a warning that one camera was not used";
}

// A real file: the Collada duck's camera (yfov 37.8492, aspect 1.5) looks at the duck.
TEST(AssimpCameras, ColladaDuckCameraLooksAtTheDuck) {
    const std::string path = "/usr/share/assimp/models/Collada/duck.dae";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (install assimp-testmodels)";
    auto r = importMesh(path);
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.cameras.size(), 1u);
    const Camera& c = r->mesh.cameras[0].camera;
    EXPECT_EQ(r->mesh.cameras[0].name, "camera1");
    EXPECT_NEAR(c.fovYDegrees, 37.8492f, 1e-3f);
    Vec3f lo = r->mesh.positions[0], hi = lo;
    for (const Vec3f& p : r->mesh.positions) lo = min(lo, p), hi = max(hi, p);
    const Vec3f toCentre = normalize((lo + hi) * 0.5f - c.eye);
    const double angle = std::acos(std::clamp(double(dot(toCentre, viewDirection(c))), -1.0, 1.0)) * 180.0 / kPi;
    EXPECT_LT(angle, 0.5 * c.fovYDegrees) << "the duck's centre is outside the camera's view";
}

}  // namespace
}  // namespace vastray::test
