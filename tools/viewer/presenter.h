// tools/viewer/presenter.h — draws images into the viewer's window (OpenGL 3.3 core, the window's
// GLX context current): uploads RGBA8 images as textures and draws them 1:1 (texelFetch, no
// filtering), centred; mixes an anaglyph of two textures in the fragment shader
// (composite::anaglyphGlsl(), the CPU composite's formula); reads the window back.
#pragma once

#include <map>

#include <epoxy/gl.h>
#include <glm/glm.hpp>

#include "mvr/composite/anaglyph.h"
#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::viewer {

class Presenter {
public:
    Presenter() = default;
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;
    ~Presenter();

    /// Builds the present program and the two textures. Errors: Internal with the GLSL log.
    Status init();

    /// Uploads `image` (RGBA8, row 0 at the top) into texture `slot` (0, or 1 for the right eye).
    void upload(int slot, const Image& image);

    /// The top-left corner of texture `slot` in a framebuffer of `fb` (centred).
    glm::ivec2 offset(int slot, glm::ivec2 fb) const { return (fb - mSizes[slot]) / 2; }

    /// Draws texture `slot` 1:1, centred, into `drawBuffer` (GL_BACK, GL_BACK_LEFT, …).
    void draw(int slot, glm::ivec2 fb, GLenum drawBuffer);

    /// Draws the anaglyph `method` of texture 0 (left eye) and 1 (right eye), 1:1, centred:
    /// composite::anaglyphGlsl(method), within 1/255 of the CPU composite (GPU pow() vs the
    /// CPU's sRGB tables; see src/composite/README.md).
    /// Errors: the mix shader does not compile (then the caller composes on the CPU).
    Status drawAnaglyph(composite::AnaglyphMethod method, glm::ivec2 fb, GLenum drawBuffer);

    /// Reads `readBuffer` of the window back as an image (row 0 at the top, alpha 255).
    static Image readBack(glm::ivec2 fb, GLenum readBuffer);

private:
    struct MixProgram {
        GLuint id = 0;
        GLint offsetLoc = -1, fbHeightLoc = -1;
    };

    void drawWith(GLuint program, GLint offsetLoc, GLint fbHeightLoc, int slot, glm::ivec2 fb,
                  GLenum drawBuffer);

    GLuint mProgram = 0, mVao = 0;
    std::map<composite::AnaglyphMethod, MixProgram> mAnaglyphPrograms;
    GLuint mTextures[2] = {0, 0};
    glm::ivec2 mSizes[2] = {glm::ivec2(0), glm::ivec2(0)};
    GLint mOffsetLoc = -1, mFbHeightLoc = -1;
};

}  // namespace mvr::viewer
