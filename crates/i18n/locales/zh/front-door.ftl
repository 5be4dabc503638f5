# 第一次使用的页面和今天的页面。句子简短，用词日常。

## 选择语言
front-language-title = 请选择您的语言
front-language-how = 转动方向盘选择，然后按一个按钮。

## 连接诊所
front-pairing-title = 欢迎
front-pairing-card = 已找到您诊所的配对卡。
front-pairing-card-press = 按方向盘上的按钮即可连接。
front-pairing-card-bad = 无法读取诊所的配对卡。请给您的诊所打电话。
front-pairing-ask-clinic = 这台电脑还不认识您的诊所。
front-pairing-call-clinic = 请给您的诊所打电话，他们会帮您设置。
front-pairing-code-intro = 请输入诊所来信上的代码。
front-pairing-code-how = 转动方向盘选择字符，按下即可选定。
front-pairing-code-back = 按住按钮可删除一个字符。
front-pairing-code-label = 配对代码
front-pairing-address-label = 诊所地址
front-pairing-keys = 键盘：直接输入，按回车继续，按 Tab 改地址。
front-connecting-title = 正在连接您的诊所
front-connecting-wait = 请稍等。
front-connected = 这台电脑已连接到您的诊所。

## 连接出错（代码会保留在页面上）
front-error-code = 这个代码不对。请对照诊所的来信。
front-error-code-length = 代码有 8 个字符。请对照诊所的来信。
front-error-unreachable = 无法连接诊所。请检查网络，然后再按一次。
front-error-refused = 诊所不接受这个代码。请对照来信检查。
front-error-not-authentic = 这个回复不是来自您的诊所，没有保存任何内容。
front-error-save = 已连接，但电脑无法保存。请给诊所打电话。
front-error-other = 连接没有成功。请给您的诊所打电话。
front-error-no-address = 请先输入诊所的地址。

## 今天
front-today-title = 今天的训练
front-today-summary = { $exercises } 个练习，约 { $minutes } 分钟（含休息）
front-today-no-plan = 您的诊所还没有发来训练计划。
front-today-unbuildable = 这台电脑无法显示的练习
front-today-checking = 正在检查方向盘……
front-today-how = 转动方向盘选择，然后按一个按钮。
front-today-wait-wheel = 方向盘准备好后就可以开始。
front-today-start = 开始
front-today-practice = 练习
front-today-close = 关闭
front-today-keys = 键盘：空格键开始，F2 练习，Esc 关闭。
front-today-offline = 现在连不上您的诊所。训练记录会先保存在这里。
front-today-message = 治疗师给您的留言：

## 设备
front-device-no-wheel = 没有找到方向盘。请插上并打开电源。
front-device-wheel = 方向盘：{ $name }
front-device-wheel-unknown = 在诊所设置之前，它的力量会保持较小。
front-device-simulated = 方向盘：屏幕上的练习方向盘
front-device-permission = 这台电脑还不能使用方向盘。请给诊所打电话。
front-device-arm-sensors = 手臂传感器：{ $names }
front-device-no-arm-sensors = 没有手臂传感器，训练照常进行。

## 练习
front-practice-banner = 练习 · 不会保存任何内容
