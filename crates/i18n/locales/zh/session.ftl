# 训练时的各个画面。称呼用“您”。每句话尽量简短。

## 练习名称
exercise-straight-road = 直路
exercise-sine-road = 弯弯的路
exercise-triangle-road = 之字形的路
exercise-clothoid-road = 越来越急的弯
exercise-sharp-turns = 急转弯
exercise-s-bend = 连续弯道
exercise-lane-change = 换车道
exercise-slalom = 绕过路锥
exercise-dial-sine = 跟着指针转
exercise-dial-multi-sine = 跟着来回移动的指针转
exercise-dial-step = 跟着跳动的指针转
exercise-dial-ramp = 跟着慢慢移动的指针转
exercise-dial-chirp = 跟着越来越快的指针转
exercise-strength = 推方向盘
exercise-haptic-sweep = 感受方向盘
exercise-assessment-range = 测试：能转多远
exercise-assessment-tracking-slow = 测试：跟着慢指针转
exercise-assessment-tracking-medium = 测试：跟着指针转
exercise-assessment-tracking-fast = 测试：跟着快指针转
exercise-assessment-steps = 测试：跟着跳动的指针转
exercise-assessment-strength = 测试：推方向盘
exercise-other = 练习

## 每项练习要做什么
instruction-dial = 转动方向盘。让黑色指针对准红色指针。
instruction-strength = 先向左推方向盘，再向右推。用力到您觉得舒服为止。
instruction-slalom = 绕着路锥开。不要开出路面。
instruction-lane-change = 道路移开时，请换到另一条车道。
instruction-straight-road = 让车保持在车道中间。
instruction-bends = 开过弯道。保持在您的车道内。
instruction-road = 沿着道路开。保持在您的车道内。
instruction-pedals = 用脚控制速度。踩右踏板前进，踩左踏板减速。
instruction-assessment-range = 尽量把方向盘向左转，再向右转。保持住。
instruction-assessment-tracking = 这是一次测试。方向盘不会帮忙。让黑色指针对准红色指针。
instruction-assessment-steps = 红色指针会跳动。尽快跟上它。

## 练习前和练习之间的卡片
card-get-ready = 准备开始
card-rest-then-back = 休息，然后回到
card-rest-then-next = 休息。下一项：
card-next = 下一项
card-exercise-of = 第 { $number } 项，共 { $total } 项：{ $name }
card-start-key = 空格键或方向盘按钮：开始
card-go-on-now-key = 空格键或方向盘按钮：现在继续
card-message-from-therapist = 您的治疗师给您留言：

## 暂停，以及提前结束前的确认
pause-title = 已暂停
end-confirm-title = 要结束训练吗？
end-confirm-yes = 再按一次 Esc 结束。
end-confirm-no = 按空格键继续。

## 简单的卡片
card-press-space-to-start = 按空格键开始。
card-all-done = 全部完成

## 准备手臂传感器
setup-hold-still = 请握住方向盘不动
setup-hold-still-how = 双手放在方向盘上。放松。
setup-turn-slowly = 请慢慢转动方向盘
setup-turn-slowly-how = 向左再向右，转到您觉得舒服为止。
setup-thank-you = 谢谢
setup-getting-ready = 正在准备手臂传感器…
setup-seconds-left = { $seconds } 秒

## 练习时的显示
hud-time-left = 剩余时间
hud-in-lane = 在车道内：{ $percent }%
hud-middle-close = 接近中间
hud-middle-off = 稍微偏离中间
hud-middle-far = 离中间很远
hud-needle-close = 正对红色指针
hud-needle-near = 接近红色指针
hud-needle-behind = 请努力跟上
hud-push-left = 向左推方向盘，用力到您觉得舒服为止。
hud-push-right = 向右推方向盘，用力到您觉得舒服为止。
hud-let-go = 松开方向盘，休息一下。
hud-speed = { $kmh } 公里/小时
hud-help = 辅助：{ $percent }%
hud-press-pedal = 踩右踏板开车。
hud-sit-up = 请重新坐直。
hud-wheel-working = 方向盘：正常
hud-wheel-resting = 方向盘：休息中
hud-wheel-stopping = 方向盘：正在停止
hud-wheel-problem = 方向盘：有问题，力度已关闭
hud-wheel-simulated = 方向盘：练习模式
hud-gentle-force = 只用轻柔的力度
hud-arm-working = 手臂传感器：正常
hud-arm-setting-up = 手臂传感器：准备中
hud-arm-not-working = 手臂传感器：不工作
hud-arm-not-answering = 手臂传感器：没有信号
hud-arm-simulated = 手臂传感器：练习模式
hud-your-arm = 您的手臂
hud-your-wheel = 您的方向盘
hud-target = 目标
hud-your-arm-measured = 您的手臂（已测量）

## 训练无法开始时
cannot-start-title = 训练还不能开始
cannot-start-then = 然后请重新打开 telerehab。
cannot-start-close-key = 按任意键关闭。

## 画面重新启动时
pause-screen-restarted = 屏幕重新启动了，所以练习暂停了。
