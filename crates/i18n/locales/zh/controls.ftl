# 训练中由方向盘回答的卡片。按 = 短按；按住 = 1.5 秒。

controls-paused-title = 已暂停
controls-paused-go-on = 继续
controls-paused-rest = 休息
controls-paused-end = 结束
controls-paused-how = 转动选择，然后按一个按钮。
controls-paused-keys = 键盘：空格键继续，R 休息，Esc 结束。
controls-end-title = 现在结束吗？
controls-end-press = 按一下按钮：结束。
controls-end-hold = 按住按钮：继续。
controls-end-keys = 键盘：Esc 结束，空格键继续。
controls-ready-title = 准备好了吗？
controls-ready-press = 按方向盘上的按钮开始。
controls-ready-countdown = { $seconds } 秒后开始。
controls-unplugged-title = 请把方向盘重新插好
controls-unplugged-waits = 练习会等您。
controls-unplugged-left = 训练将在 { $seconds } 秒后结束。
controls-unplugged-keys = 线缆连接方向盘和电脑。
controls-arm-unplugged-title = 请把手臂传感器重新插好
controls-arm-unplugged-keys = 手臂上的传感器用线缆连接电脑。
controls-start = 按方向盘上的按钮开始。
controls-go-on-now = 按方向盘上的按钮马上继续。
