#include "VtkViewport.h"

#include <vtkAxesActor.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLightKit.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>

#include <QCursor>
#include <QElapsedTimer>
#include <QGuiApplication>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QScreen>
#include <QWheelEvent>
#include <algorithm>
#include <ctime>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace aero::ui {

namespace {

// Trackball camera whose keyboard shortcuts are limited to what makes sense inside a Qt
// widget: 'r' resets the camera, 'w' / 's' switch wireframe / surface. The stock style also
// exits on 'e'/'q', toggles stereo on '3', picks on 'p' and switches styles on 'j'/'t', none of
// which the host supports.
class ViewportCameraStyle : public vtkInteractorStyleTrackballCamera {
  public:
    static ViewportCameraStyle* New();

    void OnChar() override {
        switch (this->Interactor->GetKeyCode()) {
            case 'r':
            case 'R':
            case 'w':
            case 'W':
            case 's':
            case 'S':
                vtkInteractorStyleTrackballCamera::OnChar();
                break;
            default:
                break;
        }
    }

    vtkTypeMacro(ViewportCameraStyle, vtkInteractorStyleTrackballCamera)
};
vtkStandardNewMacro(ViewportCameraStyle);

Qt::CursorShape qtCursor(int vtkCursor) {
    switch (vtkCursor) {
        case VTK_CURSOR_SIZENE:
        case VTK_CURSOR_SIZESW:
            return Qt::SizeBDiagCursor;
        case VTK_CURSOR_SIZENW:
        case VTK_CURSOR_SIZESE:
            return Qt::SizeFDiagCursor;
        case VTK_CURSOR_SIZENS:
            return Qt::SizeVerCursor;
        case VTK_CURSOR_SIZEWE:
            return Qt::SizeHorCursor;
        case VTK_CURSOR_SIZEALL:
            return Qt::SizeAllCursor;
        case VTK_CURSOR_HAND:
            return Qt::PointingHandCursor;
        case VTK_CURSOR_CROSSHAIR:
            return Qt::CrossCursor;
        default:
            return Qt::ArrowCursor;
    }
}

// X11 keysym names (what VTK's interactor styles and widgets compare against) for the keys
// that have no printable text. Empty when there is none.
const char* keySymName(int key) {
    static constexpr struct {
        int key;
        const char* sym;
    } kTable[] = {
        {Qt::Key_Left, "Left"},     {Qt::Key_Right, "Right"},   {Qt::Key_Up, "Up"},
        {Qt::Key_Down, "Down"},     {Qt::Key_Return, "Return"}, {Qt::Key_Enter, "KP_Enter"},
        {Qt::Key_Escape, "Escape"}, {Qt::Key_Tab, "Tab"},       {Qt::Key_Backspace, "BackSpace"},
        {Qt::Key_Delete, "Delete"}, {Qt::Key_Insert, "Insert"}, {Qt::Key_Home, "Home"},
        {Qt::Key_End, "End"},       {Qt::Key_PageUp, "Prior"},  {Qt::Key_PageDown, "Next"},
        {Qt::Key_Space, "space"},   {Qt::Key_Shift, "Shift_L"}, {Qt::Key_Control, "Control_L"},
        {Qt::Key_Alt, "Alt_L"},     {Qt::Key_Plus, "plus"},     {Qt::Key_Minus, "minus"},
        {Qt::Key_F1, "F1"},         {Qt::Key_F2, "F2"},         {Qt::Key_F3, "F3"},
        {Qt::Key_F4, "F4"},         {Qt::Key_F5, "F5"},         {Qt::Key_F6, "F6"},
        {Qt::Key_F7, "F7"},         {Qt::Key_F8, "F8"},         {Qt::Key_F9, "F9"},
        {Qt::Key_F10, "F10"},       {Qt::Key_F11, "F11"},       {Qt::Key_F12, "F12"},
    };
    for (const auto& entry : kTable)
        if (entry.key == key) return entry.sym;
    return "";
}

}  // namespace

namespace {

// CPU time of the calling thread, ms.
double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

}  // namespace

struct VtkViewport::Impl {
    VtkViewport* q;
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    vtkNew<vtkRenderer> renderer;
    vtkNew<vtkGenericRenderWindowInteractor> interactor;
    vtkNew<ViewportCameraStyle> style;
    vtkNew<vtkOrientationMarkerWidget> axesWidget;
    std::vector<std::pair<vtkObject*, unsigned long>> observers;

    bool glReady = false;   // InitializeFromCurrentContext() ran in the current context
    bool painting = false;  // inside paintGL()
    int frames = 0;
    double frameMs = 0, longestFrameMs = 0, totalFrameMs = 0;  // VTK's render time in paintGL
    double totalFrameCpuMs = 0;  // ... and the GUI thread's CPU time in it
    int wheelAccumulator = 0;

    explicit Impl(VtkViewport* owner) : q(owner) {}

    template <class Method>
    void observe(vtkObject* subject, unsigned long event, Method method) {
        observers.emplace_back(subject, subject->AddObserver(event, this, method));
    }

    // --- vtkGenericOpenGLRenderWindow callbacks: the window asks us about OUR context.
    void onMakeCurrent(vtkObject*, unsigned long, void*) {
        // Only switch when needed: QOpenGLWidget::makeCurrent() also rebinds the widget's
        // framebuffer object, which must not happen while VTK has its own FBO bound.
        if (q->context() && QOpenGLContext::currentContext() != q->context()) q->makeCurrent();
    }
    void onIsCurrent(vtkObject*, unsigned long, void* callData) {
        *static_cast<bool*>(callData) =
            q->context() != nullptr && QOpenGLContext::currentContext() == q->context();
    }
    void onSupportsOpenGL(vtkObject*, unsigned long, void* callData) {
        *static_cast<int*>(callData) = q->context() && q->context()->isValid() ? 1 : 0;
    }
    void onIsDirect(vtkObject*, unsigned long, void* callData) { *static_cast<int*>(callData) = 1; }
    void onCursorChanged(vtkObject*, unsigned long, void* callData) {
        q->setCursor(qtCursor(*static_cast<int*>(callData)));
    }
    // --- interactor: styles and widgets ask for a render; we paint on the next update.
    void onRenderRequest(vtkObject*, unsigned long, void*) {
        if (!painting) q->update();
    }

    /// Qt logical position -> VTK framebuffer pixel (origin bottom-left).
    void setEventPosition(const QPointF& pos, Qt::KeyboardModifiers mods, int repeat = 0) {
        const qreal dpr = q->devicePixelRatioF();
        const int x = static_cast<int>(std::lround(pos.x() * dpr));
        const int y = interactor->GetSize()[1] - 1 - static_cast<int>(std::lround(pos.y() * dpr));
        interactor->SetEventInformation(x, y, (mods & Qt::ControlModifier) ? 1 : 0,
                                        (mods & Qt::ShiftModifier) ? 1 : 0, 0, repeat, nullptr);
        interactor->SetAltKey((mods & Qt::AltModifier) ? 1 : 0);
    }

    void forwardKey(QKeyEvent* e, unsigned long vtkEvent) {
        const QString text = e->text();
        char code = 0;
        if (text.size() == 1 && text.at(0).unicode() >= 32 && text.at(0).unicode() < 127)
            code = static_cast<char>(text.at(0).unicode());
        std::string sym = keySymName(e->key());
        if (sym.empty() && code != 0) sym = std::string(1, code);
        const auto mods = e->modifiers();
        interactor->SetKeyEventInformation((mods & Qt::ControlModifier) ? 1 : 0,
                                           (mods & Qt::ShiftModifier) ? 1 : 0, code,
                                           e->isAutoRepeat() ? 1 : 0, sym.c_str());
        interactor->SetAltKey((mods & Qt::AltModifier) ? 1 : 0);
        interactor->InvokeEvent(vtkEvent, e);
        if (vtkEvent == vtkCommand::KeyPressEvent && code != 0)
            interactor->InvokeEvent(vtkCommand::CharEvent, e);
    }
};

QSurfaceFormat VtkViewport::defaultFormat() {
    QSurfaceFormat f;
    f.setRenderableType(QSurfaceFormat::OpenGL);
    f.setVersion(3, 2);
    f.setProfile(QSurfaceFormat::CoreProfile);
    f.setRedBufferSize(8);
    f.setGreenBufferSize(8);
    f.setBlueBufferSize(8);
    f.setAlphaBufferSize(8);
    f.setDepthBufferSize(24);
    f.setStencilBufferSize(8);
    f.setSamples(0);
    f.setSwapBehavior(QSurfaceFormat::DoubleBuffer);
    return f;
}

VtkViewport::VtkViewport(QWidget* parent)
    : QOpenGLWidget(parent), d_(std::make_unique<Impl>(this)) {
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(true);
    setMinimumSize(200, 150);

    auto& w = *d_->window;
    // The context belongs to Qt; VTK must neither create nor swap nor blit to window 0. It
    // renders into its own FBOs and, at the end of Frame(), blits into whatever draw
    // framebuffer is bound: inside paintGL() that is QOpenGLWidget's FBO.
    w.SetOwnContext(false);
    w.SetFrameBlitModeToBlitToCurrent();
    w.SetReadyForRendering(false);  // true only inside paintGL()
    w.SetMultiSamples(4);           // VTK's own MSAA (Qt's FBO is single-sampled)
    w.SetMapped(1);
    w.AddRenderer(d_->renderer);

    d_->observe(&w, vtkCommand::WindowMakeCurrentEvent, &Impl::onMakeCurrent);
    d_->observe(&w, vtkCommand::WindowIsCurrentEvent, &Impl::onIsCurrent);
    d_->observe(&w, vtkCommand::WindowSupportsOpenGLEvent, &Impl::onSupportsOpenGL);
    d_->observe(&w, vtkCommand::WindowIsDirectEvent, &Impl::onIsDirect);
    d_->observe(&w, vtkCommand::CursorChangedEvent, &Impl::onCursorChanged);

    auto& iren = *d_->interactor;
    iren.SetRenderWindow(&w);
    // The interactor never renders by itself: Render() only fires RenderEvent, which we turn
    // into QWidget::update() so that every render happens in paintGL().
    iren.EnableRenderOff();
    iren.SetInteractorStyle(d_->style);
    d_->style->SetDefaultRenderer(d_->renderer);
    d_->observe(&iren, vtkCommand::RenderEvent, &Impl::onRenderRequest);
    iren.Initialize();

    // Default look: white-to-light-grey gradient, a light kit instead of the bare headlight.
    auto& ren = *d_->renderer;
    ren.GradientBackgroundOn();
    ren.SetBackground(0.80, 0.82, 0.86);  // bottom
    ren.SetBackground2(1.0, 1.0, 1.0);    // top
    ren.SetBackgroundAlpha(1.0);
    ren.AutomaticLightCreationOff();
    vtkNew<vtkLightKit> lights;
    lights->SetKeyLightIntensity(0.85);
    lights->AddLightsToRenderer(&ren);

    vtkNew<vtkAxesActor> axes;
    axes->SetShaftTypeToCylinder();
    axes->SetCylinderRadius(0.03);
    axes->SetConeRadius(0.5);
    axes->SetTotalLength(1.0, 1.0, 1.0);
    for (vtkCaptionActor2D* label : {axes->GetXAxisCaptionActor2D(), axes->GetYAxisCaptionActor2D(),
                                     axes->GetZAxisCaptionActor2D()}) {
        vtkTextProperty* text = label->GetCaptionTextProperty();
        text->SetColor(0.15, 0.15, 0.15);
        text->ShadowOff();
        text->ItalicOff();
        text->BoldOn();
    }
    d_->axesWidget->SetOrientationMarker(axes);
    d_->axesWidget->SetInteractor(&iren);
    d_->axesWidget->SetViewport(0.0, 0.0, 0.2, 0.28);
    d_->axesWidget->SetEnabled(1);
    d_->axesWidget->InteractiveOff();
}

VtkViewport::~VtkViewport() {
    // VTK releases GL objects while being destroyed; keep our context current for that and
    // stop routing VTK's callbacks into a widget that is going away.
    const bool current = context() != nullptr;
    if (current) {
        disconnect(context(), nullptr, this, nullptr);  // the base class destroys the context
        makeCurrent();
    }
    d_->axesWidget->SetEnabled(0);
    for (auto& [subject, tag] : d_->observers) subject->RemoveObserver(tag);
    d_->observers.clear();
    if (d_->glReady) d_->window->Finalize();
    d_->glReady = false;
    d_.reset();
    if (current) doneCurrent();
}

vtkRenderer* VtkViewport::renderer() const {
    return d_->renderer;
}
vtkGenericOpenGLRenderWindow* VtkViewport::renderWindow() const {
    return d_->window;
}
vtkRenderWindowInteractor* VtkViewport::interactor() const {
    return d_->interactor;
}
int VtkViewport::renderedFrames() const {
    return d_->frames;
}

VtkViewport::FrameTimes VtkViewport::frameTimes() const {
    return {d_->frames, d_->frameMs, d_->longestFrameMs, d_->totalFrameMs, d_->totalFrameCpuMs};
}

void VtkViewport::resetLongestFrame() {
    d_->longestFrameMs = 0;
}

void VtkViewport::requestRender() {
    update();
}

QImage VtkViewport::grabImage() {
    // grabFramebuffer() initializes the widget if needed and calls paintGL() itself.
    QImage image = grabFramebuffer();
    if (image.isNull()) return image;
    return image.convertToFormat(QImage::Format_RGB32);
}

bool VtkViewport::project(const std::array<double, 3>& world, QPointF* widget, double* depth) const {
    const int* size = d_->window->GetSize();
    if (size[0] <= 1 || size[1] <= 1) return false;
    vtkRenderer* ren = d_->renderer;
    // Camera space first: points at or behind the eye do not project.
    vtkCamera* cam = ren->GetActiveCamera();
    double pos[3], dir[3];
    cam->GetPosition(pos);
    cam->GetDirectionOfProjection(dir);
    if (!cam->GetParallelProjection()) {
        const double ahead = (world[0] - pos[0]) * dir[0] + (world[1] - pos[1]) * dir[1] + (world[2] - pos[2]) * dir[2];
        if (ahead <= 0) return false;
    }
    ren->SetWorldPoint(world[0], world[1], world[2], 1.0);
    ren->WorldToDisplay();
    double display[3];
    ren->GetDisplayPoint(display);
    const qreal dpr = devicePixelRatioF();
    // VTK display pixels: origin bottom-left, framebuffer pixels (see Impl::setEventPosition).
    if (widget) *widget = QPointF(display[0] / dpr, (size[1] - 1 - display[1]) / dpr);
    if (depth) *depth = display[2];
    return true;
}

void VtkViewport::pickRay(const QPointF& widget, std::array<double, 3>& origin, std::array<double, 3>& direction) const {
    vtkRenderer* ren = d_->renderer;
    const int* size = d_->window->GetSize();
    const qreal dpr = devicePixelRatioF();
    const double x = widget.x() * dpr, y = size[1] - 1 - widget.y() * dpr;
    double nearP[4], farP[4];
    ren->SetDisplayPoint(x, y, 0.0);
    ren->DisplayToWorld();
    ren->GetWorldPoint(nearP);
    ren->SetDisplayPoint(x, y, 1.0);
    ren->DisplayToWorld();
    ren->GetWorldPoint(farP);
    for (double* p : {nearP, farP})
        if (p[3] != 0)
            for (int k = 0; k < 3; ++k) p[k] /= p[3];
    double len = 0;
    for (int k = 0; k < 3; ++k) {
        origin[static_cast<size_t>(k)] = nearP[k];
        direction[static_cast<size_t>(k)] = farP[k] - nearP[k];
        len += direction[static_cast<size_t>(k)] * direction[static_cast<size_t>(k)];
    }
    len = std::sqrt(len);
    if (len > 0)
        for (double& c : direction) c /= len;
    else
        direction = viewDirection();
}

std::array<double, 3> VtkViewport::viewDirection() const {
    std::array<double, 3> dir{};
    d_->renderer->GetActiveCamera()->GetDirectionOfProjection(dir.data());
    return dir;
}

void VtkViewport::setOrientationAxesVisible(bool visible) {
    d_->axesWidget->SetEnabled(visible ? 1 : 0);
    if (visible) d_->axesWidget->InteractiveOff();
    update();
}

bool VtkViewport::orientationAxesVisible() const {
    return d_->axesWidget->GetEnabled() != 0;
}

void VtkViewport::initializeGL() {
    // A QOpenGLWidget gets a new context when it moves to another top-level window; release
    // VTK's GL objects with the old one, re-initialize with the new one here.
    connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &VtkViewport::releaseGraphics,
            Qt::DirectConnection);
    d_->window->SetScreenSize(screen() ? screen()->size().width() : 1920,
                              screen() ? screen()->size().height() : 1080);
    d_->window->InitializeFromCurrentContext();  // glewInit etc. in Qt's context
    d_->glReady = true;
}

void VtkViewport::releaseGraphics() {
    if (!d_ || !d_->glReady) return;
    makeCurrent();
    d_->window->Finalize();  // ReleaseGraphicsResources of the window, renderers and props
    d_->glReady = false;
    doneCurrent();
}

void VtkViewport::resizeGL(int w, int h) {
    // Qt passes device-independent pixels; VTK works in framebuffer pixels.
    const qreal dpr = devicePixelRatioF();
    const int fw = std::max(1, static_cast<int>(std::lround(w * dpr)));
    const int fh = std::max(1, static_cast<int>(std::lround(h * dpr)));
    d_->window->SetDPI(static_cast<int>(std::lround(72 * dpr)));
    d_->window->SetSize(fw, fh);
    d_->interactor->UpdateSize(fw, fh);
    d_->interactor->InvokeEvent(vtkCommand::ConfigureEvent, nullptr);
}

void VtkViewport::paintGL() {
    if (!d_->glReady) return;
    // QOpenGLWidget has made the context current and bound its FBO; VTK renders into its own
    // framebuffers and blits into the bound one at the end of Frame().
    QElapsedTimer clock;
    clock.start();
    const double cpu0 = threadCpuMs();
    d_->painting = true;
    // What is drawn changes between camera fits (a flow solution's symmetry plane, tens of radii
    // wide, appears after a fit to the geometry): near and far planes fitted to it every frame,
    // or its nearest part is cut away.
    d_->renderer->ResetCameraClippingRange();
    d_->window->SetReadyForRendering(true);
    d_->window->Render();
    d_->window->SetReadyForRendering(false);
    d_->painting = false;
    ++d_->frames;
    d_->frameMs = static_cast<double>(clock.nsecsElapsed()) * 1e-6;
    d_->longestFrameMs = std::max(d_->longestFrameMs, d_->frameMs);
    d_->totalFrameMs += d_->frameMs;
    d_->totalFrameCpuMs += threadCpuMs() - cpu0;
}

void VtkViewport::mousePressEvent(QMouseEvent* e) {
    d_->setEventPosition(e->position(), e->modifiers());
    switch (e->button()) {
        case Qt::LeftButton:
            d_->interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent, e);
            break;
        case Qt::MiddleButton:
            d_->interactor->InvokeEvent(vtkCommand::MiddleButtonPressEvent, e);
            break;
        case Qt::RightButton:
            d_->interactor->InvokeEvent(vtkCommand::RightButtonPressEvent, e);
            break;
        default:
            break;
    }
}

void VtkViewport::mouseDoubleClickEvent(QMouseEvent* e) {
    // Qt sends press, release, double-click, release; VTK expects a press with repeat = 1.
    d_->setEventPosition(e->position(), e->modifiers(), 1);
    switch (e->button()) {
        case Qt::LeftButton:
            d_->interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent, e);
            break;
        case Qt::MiddleButton:
            d_->interactor->InvokeEvent(vtkCommand::MiddleButtonPressEvent, e);
            break;
        case Qt::RightButton:
            d_->interactor->InvokeEvent(vtkCommand::RightButtonPressEvent, e);
            break;
        default:
            break;
    }
}

void VtkViewport::mouseReleaseEvent(QMouseEvent* e) {
    d_->setEventPosition(e->position(), e->modifiers());
    switch (e->button()) {
        case Qt::LeftButton:
            d_->interactor->InvokeEvent(vtkCommand::LeftButtonReleaseEvent, e);
            break;
        case Qt::MiddleButton:
            d_->interactor->InvokeEvent(vtkCommand::MiddleButtonReleaseEvent, e);
            break;
        case Qt::RightButton:
            d_->interactor->InvokeEvent(vtkCommand::RightButtonReleaseEvent, e);
            break;
        default:
            break;
    }
}

void VtkViewport::mouseMoveEvent(QMouseEvent* e) {
    d_->setEventPosition(e->position(), e->modifiers());
    d_->interactor->InvokeEvent(vtkCommand::MouseMoveEvent, e);
}

void VtkViewport::wheelEvent(QWheelEvent* e) {
    d_->setEventPosition(e->position(), e->modifiers());
    // One VTK wheel step per 120 units (a mouse notch); touchpads send smaller deltas.
    d_->wheelAccumulator += e->angleDelta().y();
    while (d_->wheelAccumulator >= 120) {
        d_->interactor->InvokeEvent(vtkCommand::MouseWheelForwardEvent, e);
        d_->wheelAccumulator -= 120;
    }
    while (d_->wheelAccumulator <= -120) {
        d_->interactor->InvokeEvent(vtkCommand::MouseWheelBackwardEvent, e);
        d_->wheelAccumulator += 120;
    }
    e->accept();
}

void VtkViewport::keyPressEvent(QKeyEvent* e) {
    d_->forwardKey(e, vtkCommand::KeyPressEvent);
}

void VtkViewport::keyReleaseEvent(QKeyEvent* e) {
    d_->forwardKey(e, vtkCommand::KeyReleaseEvent);
}

void VtkViewport::enterEvent(QEnterEvent* e) {
    d_->setEventPosition(e->position(), QGuiApplication::keyboardModifiers());
    d_->interactor->InvokeEvent(vtkCommand::EnterEvent, e);
}

void VtkViewport::leaveEvent(QEvent* e) {
    d_->interactor->InvokeEvent(vtkCommand::LeaveEvent, e);
}

}  // namespace aero::ui
