#pragma once
// A Qt6 QOpenGLWidget that hosts a VTK 9.1 scene (Debian's VTK::GUISupportQt is Qt5-only).
//
// The widget owns a vtkGenericOpenGLRenderWindow that draws with the widget's own OpenGL
// context: VTK renders into its offscreen framebuffers inside paintGL() and blits the result
// into the framebuffer object QOpenGLWidget has bound for that paint. Qt mouse, wheel, key,
// enter/leave and resize events are forwarded to a vtkGenericRenderWindowInteractor with a
// trackball-camera style; the interactor's render requests become QWidget::update() calls.
//
// Threading: GUI thread only (VTK objects included). Anyone who changes the scene calls
// requestRender() (or update()); rendering happens in the next paintGL().
#include <QOpenGLWidget>
#include <QPointF>
#include <QSurfaceFormat>
#include <array>
#include <memory>

class vtkRenderer;
class vtkGenericOpenGLRenderWindow;
class vtkRenderWindowInteractor;

namespace aero::ui {

class VtkViewport : public QOpenGLWidget {
    Q_OBJECT

  public:
    explicit VtkViewport(QWidget* parent = nullptr);
    ~VtkViewport() override;

    /// The surface format VTK needs: OpenGL 3.2 core profile, depth 24, stencil 8, RGBA8 and
    /// no multisampling on the Qt side (VTK cannot blit into a multisampled framebuffer; it
    /// does its own MSAA). Set it with QSurfaceFormat::setDefaultFormat() before the
    /// QApplication is constructed.
    static QSurfaceFormat defaultFormat();

    /// The scene's main renderer (owned by the viewport; valid for its lifetime).
    vtkRenderer* renderer() const;
    vtkGenericOpenGLRenderWindow* renderWindow() const;
    vtkRenderWindowInteractor* interactor() const;

    /// Schedules a repaint (the scene renders in the next paintGL()).
    void requestRender();

    /// The current frame as an image in device pixels (renders first if needed). Null image
    /// if the widget has no OpenGL context yet (never shown).
    QImage grabImage();

    /// Number of frames VTK has rendered so far (for tests and diagnostics).
    int renderedFrames() const;
    /// How long VTK's rendering took inside paintGL (on the GUI thread): the last frame, the
    /// longest since resetLongestFrame(), and all frames together, in milliseconds; and the GUI
    /// thread's CPU time in them. With a software OpenGL (llvmpipe under Xvfb) this is most of a
    /// frame's cost.
    struct FrameTimes {
        int frames = 0;
        double lastMs = 0, longestMs = 0, totalMs = 0;
        double totalCpuMs = 0;
    };
    FrameTimes frameTimes() const;
    void resetLongestFrame();

    // --- Screen <-> world, for tools that pick and drag in the view (widget coordinates are
    // Qt's logical pixels, origin top-left, like QMouseEvent::position()).

    /// Projects a world point into the widget. Returns false if the point is behind the camera
    /// or the viewport has no size yet. `depth` (optional) is the normalized depth in [0, 1].
    bool project(const std::array<double, 3>& world, QPointF* widget, double* depth = nullptr) const;
    /// The line of sight under a widget position: a point on it (on the near plane) and its
    /// unit direction, away from the viewer.
    void pickRay(const QPointF& widget, std::array<double, 3>& origin, std::array<double, 3>& direction) const;
    /// Unit direction the camera looks along (into the screen).
    std::array<double, 3> viewDirection() const;

    void setOrientationAxesVisible(bool visible);
    bool orientationAxesVisible() const;

    QSize sizeHint() const override { return {900, 650}; }

  protected:
    void initializeGL() override;
    void resizeGL(int w, int h) override;
    void paintGL() override;

    void mousePressEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    void mouseDoubleClickEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void wheelEvent(QWheelEvent* e) override;
    void keyPressEvent(QKeyEvent* e) override;
    void keyReleaseEvent(QKeyEvent* e) override;
    void enterEvent(QEnterEvent* e) override;
    void leaveEvent(QEvent* e) override;

  private:
    void releaseGraphics();

    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
