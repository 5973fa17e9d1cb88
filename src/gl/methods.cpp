// src/gl/methods.cpp — the draw paths of the gl backend's methods (named by the rows of
// method_table.cpp). Each binds its target, clears it, and draws every instance of the frame;
// renderOnce() times and reads back.
#include <algorithm>

#include <fmt/format.h>

#include "renderer.h"

namespace mvr::gl::detail {

namespace {
void attachLayered(GLuint fbo, GLuint color, GLuint depth) {
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, color, 0);
    glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth, 0);
}
Status checkFramebuffer(GLuint fbo, const char* what) {
    const GLenum s = glCheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER);
    if (s == GL_FRAMEBUFFER_COMPLETE) return Status::ok();
    return internalError(fmt::format("mvr::gl: {}: framebuffer incomplete (0x{:04X})", what, s));
}
}  // namespace

// multipass: the reference. One full pass of the scene per view, each into its own layer.
Status Renderer::drawMultipass(const Frame& f, GLuint prog) {
    ensureLayered(f.settings->width, f.settings->height, f.targetViews, f.samples);
    const LayeredTarget& t = mGpu->layered;
    const GLuint fbo = t.fbo.get();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    for (int v = 0; v < f.views; ++v) {
        glNamedFramebufferTextureLayer(fbo, GL_COLOR_ATTACHMENT0, t.drawColor(), 0, v);
        glNamedFramebufferTextureLayer(fbo, GL_DEPTH_ATTACHMENT, t.drawDepth(), 0, v);
        if (v == 0) {
            if (Status s = checkFramebuffer(fbo, f.method->name); !s) return s;
        }
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glProgramUniform1i(prog, 0, v);
        drawScene(f, prog, 1);
    }
    return Status::ok();
}

// gs-layered / gs-invocations: one pass; the geometry shader sends each copy to gl_Layer.
Status Renderer::drawLayeredGs(const Frame& f, GLuint prog) {
    ensureLayered(f.settings->width, f.settings->height, f.targetViews, f.samples);
    attachLayered(mGpu->layered.fbo.get(), mGpu->layered.drawColor(), mGpu->layered.drawDepth());
    if (Status s = checkFramebuffer(mGpu->layered.fbo.get(), "layered target"); !s) return s;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mGpu->layered.fbo.get());
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);  // clears every layer
    drawScene(f, prog, 1);
    return Status::ok();
}

// instanced-layer: N instances of every draw; the vertex shader picks gl_Layer = instance.
Status Renderer::drawInstancedLayer(const Frame& f, GLuint prog) {
    ensureLayered(f.settings->width, f.settings->height, f.targetViews, f.samples);
    attachLayered(mGpu->layered.fbo.get(), mGpu->layered.drawColor(), mGpu->layered.drawDepth());
    if (Status s = checkFramebuffer(mGpu->layered.fbo.get(), "layered target"); !s) return s;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mGpu->layered.fbo.get());
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    drawScene(f, prog, f.views);
    return Status::ok();
}

// multiview: GL_OVR_multiview attachments of N layers; the driver replicates the draw. Its
// own framebuffer: re-attaching one framebuffer between multiview and per-layer / layered
// attachments left NVIDIA's driver drawing views 1.. wrong after other methods had run.
Status Renderer::drawMultiview(const Frame& f, GLuint prog) {
    // One sample (GlMethod::multisample: --aa N renders sub-pixel passes).
    ensureLayered(f.settings->width, f.settings->height, f.targetViews, 1);
    const GLuint fbo = mGpu->layered.multiviewFbo.get();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glFramebufferTextureMultiviewOVR(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                     mGpu->layered.color.get(), 0, 0, f.views);
    glFramebufferTextureMultiviewOVR(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                     mGpu->layered.depth.get(), 0, 0, f.views);
    if (Status s = checkFramebuffer(fbo, "multiview target"); !s) return s;
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    drawScene(f, prog, 1);
    return Status::ok();
}

// viewport-array: one tiled target, the geometry shader picks gl_ViewportIndex = view; each
// viewport is scissored to its tile so that no view draws into its neighbour.
Status Renderer::drawViewportArray(const Frame& f, GLuint prog) {
    const TileLayout& t = *f.tiles;
    ensureTiled(t.columns * t.width, t.rows * t.height, f.samples);
    if (Status s = checkFramebuffer(mGpu->tiled.fbo.get(), "tiled target"); !s) return s;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mGpu->tiled.fbo.get());
    glViewport(0, 0, t.columns * t.width, t.rows * t.height);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (int v = 0; v < f.views; ++v) {
        const glm::ivec2 o = t.origin(v);
        glViewportIndexedf(static_cast<GLuint>(v), static_cast<float>(o.x), static_cast<float>(o.y),
                           static_cast<float>(t.width), static_cast<float>(t.height));
        glScissorIndexed(static_cast<GLuint>(v), o.x, o.y, t.width, t.height);
    }
    glEnable(GL_SCISSOR_TEST);
    drawScene(f, prog, 1);
    glDisable(GL_SCISSOR_TEST);
    return Status::ok();
}

// kalaiah-emulation: the per-triangle arrays of every mesh (before the timed draw).
Status Renderer::prepareKalaiah(const Frame& f) {
    for (std::size_t i = 0; i < f.scene->meshes.size(); ++i) {
        if (Status st = ensureKalaiahBuffers(*f.meshes[i], f.scene->meshes[i], f.views); !st)
            return st;
    }
    return Status::ok();
}

// kalaiah2007 §4: per triangle, V dummy triangles whose vertices are (corner, view); the
// triangle's corners and normals are per-instance attributes (one instance = one triangle,
// the batched form of the paper's per-triangle glDrawArrays), the viewport transform into the
// view's partition is done in the vertex shader, per-view clipping by 4 clip distances.
Status Renderer::drawKalaiah(const Frame& f, GLuint prog) {
    const TileLayout& t = *f.tiles;
    ensureTiled(t.columns * t.width, t.rows * t.height, f.samples);
    if (Status s = checkFramebuffer(mGpu->tiled.fbo.get(), "partitioned target"); !s) return s;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mGpu->tiled.fbo.get());
    glViewport(0, 0, t.columns * t.width, t.rows * t.height);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (int i = 0; i < 4; ++i) glEnable(GL_CLIP_DISTANCE0 + i);
    for (int idx : f.order) {
        const Instance& inst = f.scene->instances[static_cast<std::size_t>(idx)];
        GpuMesh& g = *f.meshes[static_cast<std::size_t>(inst.mesh)];
        setInstanceUniforms(prog, inst);
        setInstanceState(f, inst);
        glBindVertexArray(g.kalaiahVao.get());
        glDrawArraysInstanced(GL_TRIANGLES, 0, 3 * f.views, g.triangleCount);
    }
    endInstanceState(f);
    for (int i = 0; i < 4; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
    return Status::ok();
}

// sorbier2008: one pass, the geometry shader clones to left (flag 0) and right (flag 1), MRT
// with alpha-0 "discard" by blending, depth test off, instances back to front (painter's
// order by the distance of their bounds' centre from the centre eye). With `depthMap`
// (§5.2): first the left eye's depth into a depth texture, then every fragment is tested
// against it in the fragment shader.
Status Renderer::drawGsMrt(const Frame& f, GLuint prog) { return drawSorbier(f, prog, false); }
Status Renderer::drawGsDepthMap(const Frame& f, GLuint prog) { return drawSorbier(f, prog, true); }

Status Renderer::drawSorbier(const Frame& f, GLuint prog, bool depthMap) {
    const int w = f.settings->width, h = f.settings->height;
    ensureMrt(w, h, f.samples);
    Frame sorted = f;
    const glm::vec3 eye = f.rig->centerEye();
    std::vector<float> dist(f.scene->instances.size());
    for (std::size_t i = 0; i < dist.size(); ++i) {
        const Instance& inst = f.scene->instances[i];
        const glm::vec3 c = f.meshes[static_cast<std::size_t>(inst.mesh)]->bounds.center();
        dist[i] = glm::length(glm::vec3(inst.worldFromModel * glm::vec4(c, 1.0f)) - eye);
    }
    std::stable_sort(sorted.order.begin(), sorted.order.end(), [&](int a, int b) {
        return dist[static_cast<std::size_t>(a)] > dist[static_cast<std::size_t>(b)];
    });
    if (depthMap) {
        ProgramDesc preDesc = depthPrepassProgram();
        if (mVertexColors) addDefine(preDesc, "VERTEX_COLORS");  // their alpha masks too
        Result<GLuint> pre = program(depthPrepassName(), preDesc);
        if (!pre) return pre.status();
        if (Status s = checkFramebuffer(mGpu->mrt.depthFbo.get(), "depth map"); !s) return s;
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mGpu->mrt.depthFbo.get());
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(*pre);
        glProgramUniform1i(*pre, 0, 0);  // the left eye
        drawScene(sorted, *pre, 1);
        glBindTextureUnit(1, mGpu->mrt.depthMap.get());
        glUseProgram(prog);
    }
    if (Status s = checkFramebuffer(mGpu->mrt.fbo.get(), "MRT target"); !s) return s;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mGpu->mrt.fbo.get());
    const float clear[4] = {f.settings->clearColor.x, f.settings->clearColor.y,
                            f.settings->clearColor.z, 1.0f};
    glClearNamedFramebufferfv(mGpu->mrt.fbo.get(), GL_COLOR, 0, clear);
    glClearNamedFramebufferfv(mGpu->mrt.fbo.get(), GL_COLOR, 1, clear);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    drawScene(sorted, prog, 1);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glBindTextureUnit(1, 0);
    return Status::ok();
}

}  // namespace mvr::gl::detail
